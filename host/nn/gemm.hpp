#pragma once
// Matrix products for the networks, on one of three backends chosen per device (docs/design.md §6):
//   own      kernels/gemm.cl, register-blocked without local memory: fast on PoCL's CPU device;
//   tiled    kernels/gemm_tiled.cl, work-group tiles staged through __local memory: the GPU shape; on NVIDIA
//            sm_80+ also kernels/gemm_tf32.cl, the same on the tensor cores (TF32 inputs, FP32 sums);
//   clblast  CLBlast's tuned kernels on our cl_mem and queue: fast on GPUs, untuned (slow) on PoCL.
// The own kernel's register tile must fit the vector register file, which differs between CPUs (AVX-512: 32 × 16
// floats, AVX2: 16 × 8), so it has a few candidate tiles per device type, and the tiled kernel a few block shapes.
// `auto` times every candidate and CLBlast, `fp32` the same without TF32, `own` only our FP32 kernels (tiles and
// blocks), on a 4096×512×512 product once per device and driver; the times are cached
// ($XDG_CACHE_HOME/clradiosity/gemm_probe.json, else ~/.cache/...).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"

namespace clr::nn {

enum class GemmBackend { Own, Tiled, CLBlast };
enum class GemmChoice { Auto, Fp32, Own, CLBlast };
enum class Op { N, T };                            // op(X) = X or Xᵀ
enum class Act : unsigned { None = 0, Relu = 1 };  // values match ACT_* in kernels/gemm.cl

// "auto" | "fp32" | "own" | "clblast" (the engine config's `gemm` entry); anything else throws InputError.
// auto: every candidate, TF32 tensor cores included where the device has them; fp32: every FP32 candidate;
// own: our FP32 kernels only; clblast: CLBlast alone.
GemmChoice parse_gemm_choice(const std::string& text);
std::string to_string(GemmBackend backend);

// A work-item of the own kernel computes tm rows × (vw·nv) columns of C (TM, VW, NV in kernels/gemm.cl).
struct GemmTile {
  unsigned tm, vw, nv;
  unsigned columns() const { return vw * nv; }
};
// A work-group of the tiled kernel computes bm × bn of C from bk-deep panels of A and B staged in __local memory;
// each of its (bm/wm)·(bn/wn) work-items keeps wm × wn of C in registers (BM, BN, BK, WM, WN in gemm_tiled.cl).
// vec 4: the work-item's rows and columns in runs of 4, read from local memory as float4 (VEC in gemm_tiled.cl).
// tf32: the tensor-core form (gemm_tf32.cl, NVIDIA sm_80 and later): groups of bm/wm warps (bn/wn = 32 lanes), each
// lane holding wm × wn accumulators of m16n8k8 fragments; products within the TF32 bound, not FP32's. stages 2
// (tf32 only): the panels double-buffered in local memory, one barrier a panel instead of two (STAGES).
struct GemmBlock {
  unsigned bm, bn, bk, wm, wn, vec;
  bool tf32 = false;
  unsigned stages = 1;
  std::size_t group_columns() const { return bn / wn; }  // the work-group's extent in dimension 0
  std::size_t group_rows() const { return bm / wm; }
  std::size_t local_bytes() const {  // As (padded), Bs (padded for tf32), each `stages` times
    return tf32 ? sizeof(float) * stages * (bm * (bk + 4) + bk * (bn + 8))
                : sizeof(float) * bk * ((bm + (vec == 4 ? 4 : 1)) + bn);
  }
};
// What a Gemm runs: the backend, the tile of the own kernel (`own`) and the block of the tiled one (`tiled`).
struct GemmPlan {
  GemmBackend backend;
  GemmTile tile;
  GemmBlock block{};
};
// "clblast", "own TMxVWxNV" (e.g. "own 6x16x1"), "tiled BMxBNxBK/WMxWN" (e.g. "tiled 64x64x16/4x4", "v4" after a
// float4 block) or "tf32 BMxBNxBK/WMxWN" ("db" after a double-buffered one)
std::string to_string(const GemmPlan& plan);

// The own kernel's candidate tiles for this device, the first being the default when nothing is timed.
std::vector<GemmTile> gemm_tiles(const cl::DeviceInfo& device);
// The tiled kernel's candidate blocks for this device (all within NVIDIA's 48 KiB and 1024 work-items); none on CPUs.
// TF32 blocks only where nv_compute_capability >= 80.
std::vector<GemmBlock> gemm_blocks(const cl::DeviceInfo& device);
// The tiled kernel's build options for `block` on `device`: a TF32 block on a device that runs no PTX (a test's
// context that reports a compute capability over PoCL) is built with the two PTX instructions emulated.
std::string gemm_block_options(const GemmBlock& block, const cl::DeviceInfo& device);

// A row-major matrix inside a buffer: element (i, j) is at buf[offset + i·ld + j].
struct MatRef {
  const cl::Buffer<float>* buf;
  std::size_t offset;
  std::size_t ld;
};
inline MatRef mat(const cl::Buffer<float>& b, std::size_t ld, std::size_t offset = 0) { return {&b, offset, ld}; }

// Applied to every output element after the product: C = act(alpha·op(A)·op(B) + beta·C + bias[column]).
struct Epilogue {
  const cl::Buffer<float>* bias = nullptr;  // bias[column] at bias->offset + column
  std::size_t bias_offset = 0;
  Act act = Act::None;
};

class Gemm {
 public:
  Gemm(cl::Context& ctx, GemmChoice choice = GemmChoice::Auto);
  Gemm(cl::Context& ctx, const GemmPlan& plan);

  GemmBackend backend() const { return plan_.backend; }
  const GemmPlan& plan() const { return plan_; }

  // C[m×n] = act(alpha · op(A)[m×k] · op(B)[k×n] + beta · C + bias). With beta == 0, C is not read.
  void run(Op op_a, Op op_b, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b, float beta,
           MatRef c, const Epilogue& epilogue = {});

 private:
  void run_own(Op op_a, Op op_b, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b,
               float beta, MatRef c, const Epilogue& epilogue);
  void run_clblast(Op op_a, Op op_b, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b,
                   float beta, MatRef c, const Epilogue& epilogue);
  void run_narrow(Op op_a, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b, float beta,
                  MatRef c, const Epilogue& epilogue);
  cl::Buffer<float>& scratch(std::optional<cl::Buffer<float>>& slot, std::size_t count);

  cl::Context* ctx_;
  GemmPlan plan_;
  std::optional<cl::Kernel> gemm_, reduce_, transpose_, bias_act_, narrow_nn_, narrow_tn_, zero_;
  std::optional<cl::Buffer<float>> transposed_b_, partials_, narrow_bt_;
};

// The fastest plan for `choice` on this device (CLBlast needs no timing). Timing a candidate costs a kernel build
// and a few hundred ms; times are cached on disk keyed by device name and driver version, so later runs pay nothing.
// A TF32 candidate is taken only where its product stays within tf32_error_bound of the FP32 kernel's.
GemmPlan choose_gemm_plan(cl::Context& ctx, GemmChoice choice);

// The error TF32 products are allowed against the exact product: each factor rounded to 10 mantissa bits (unit
// roundoff 2^-11), so |C − C_exact| ≤ 2^-9 · |alpha| · Σ_k |A_ik · B_kj| with room for the FP32 sum
// (kernels/gemm_tf32.cl). `magnitude` is |alpha| · Σ_k |A_ik · B_kj|.
inline double tf32_error_bound(double magnitude) { return magnitude / 512.0; }

// Checked narrowing for kernel arguments: kernels index with 32-bit integers (buffers are ≤ 1 GiB on PoCL).
unsigned u32(std::size_t v);

}  // namespace clr::nn
