#pragma once
// Every OpenCL program the host builds, in one place: the kernel files in the order cl::Context::program
// concatenates them, and the -D options of each variant. Host code builds its programs from these names and
// option builders, and tests/cl/nvptx_compile_test.cpp compiles every_build() for NVIDIA's target exactly as the
// host composes it (docs/nvidia.md). A new program belongs here, or that test never sees it.
// The list names files of rooms above nn (the vMF mixture, the RHS, the gradient exchange) only as file names.
#include <cstddef>
#include <string>
#include <vector>

#include "cl/device.hpp"

namespace clr::nn {
struct GemmBlock;
}

namespace clr::nn::programs {

using Files = std::vector<std::string>;

// atomics.cl first wherever a kernel uses atomic_add_f32.
inline const Files adam = {"atomics.cl", "adam.cl"};
inline const Files loss = {"atomics.cl", "loss.cl"};
inline const Files gemm = {"gemm.cl"};
inline const Files gemm_tiled = {"gemm.cl", "gemm_tiled.cl"};  // gemm.cl's epilogue and helper kernels too
inline const Files gemm_tf32 = {"gemm.cl", "gemm_tf32.cl"};    // NVIDIA sm_80+ only (inline PTX)
inline const Files hashgrid = {"atomics.cl", "hashgrid.cl"};
inline const Files mlp = {"mlp.cl"};
inline const Files mlp_fused = {"mlp_fused.cl"};
inline const Files sh = {"sh.cl"};
inline const Files radiosity = {"radiosity.cl"};
inline const Files vmf = {"atomics.cl", "vmf.cl", "guide.cl"};
inline const Files exchange = {"exchange.cl"};

std::string gemm_options(unsigned tm, unsigned vw, unsigned nv);
std::string gemm_tiled_options(const GemmBlock& block);
std::string hashgrid_options(unsigned features, bool fixed_point_grad);
std::string mlp_fused_options(unsigned inputs, unsigned width, unsigned hidden_layers, unsigned outputs);
std::string exchange_options(bool int64_grads);

// Whether the fused MLP kernel takes this shape (otherwise the per-layer GEMMs run).
bool mlp_fused_fits(std::size_t width, std::size_t hidden_layers, std::size_t outputs);

struct Build {
  std::string name;  // for messages and test names: "hashgrid_F2_fixed"
  Files files;
  std::string options;
};

// Every (files, options) the host may build on `device`: the GEMM at each tile and block its probe may pick
// for the device's type, the hash grid at each feature count (fixed-point gradients where the device has int64
// atomics), the fused MLP at each shape it accepts (with `fused_inputs` inputs), the gradient exchange for both
// gradient types, and the programs without variants.
std::vector<Build> every_build(const cl::DeviceInfo& device, unsigned fused_inputs = 16);

}  // namespace clr::nn::programs
