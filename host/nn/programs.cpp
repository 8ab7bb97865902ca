#include "nn/programs.hpp"

#include "nn/gemm.hpp"

namespace clr::nn::programs {

std::string gemm_options(unsigned tm, unsigned vw, unsigned nv) {
  return "-DTM=" + std::to_string(tm) + " -DVW=" + std::to_string(vw) + " -DNV=" + std::to_string(nv);
}

std::string gemm_tiled_options(const GemmBlock& b) {
  return "-DBM=" + std::to_string(b.bm) + " -DBN=" + std::to_string(b.bn) + " -DBK=" + std::to_string(b.bk) +
         " -DWM=" + std::to_string(b.wm) + " -DWN=" + std::to_string(b.wn) + " -DVEC=" + std::to_string(b.vec) +
         " -DSTAGES=" + std::to_string(b.stages);
}

std::string hashgrid_options(unsigned features, bool fixed_point_grad) {
  return "-DF=" + std::to_string(features) + (fixed_point_grad ? " -DFIXED_POINT_GRAD" : "");
}

std::string mlp_fused_options(unsigned inputs, unsigned width, unsigned hidden_layers, unsigned outputs) {
  return "-DIN=" + std::to_string(inputs) + " -DWIDTH=" + std::to_string(width) +
         " -DHIDDEN=" + std::to_string(hidden_layers) + " -DOUT=" + std::to_string(outputs);
}

std::string exchange_options(bool int64_grads) { return int64_grads ? "-DGRAD_T=long" : "-DGRAD_T=float"; }

bool mlp_fused_fits(std::size_t width, std::size_t hidden_layers, std::size_t outputs) {
  return width % 16 == 0 && width <= 64 && outputs % 16 == 0 && outputs <= 64 && hidden_layers >= 1 &&
         hidden_layers <= 4;
}

std::vector<Build> every_build(const cl::DeviceInfo& device, unsigned fused_inputs) {
  std::vector<Build> out = {{"adam", adam, ""}, {"loss", loss, ""},           {"mlp", mlp, ""},
                            {"sh", sh, ""},     {"radiosity", radiosity, ""}, {"vmf", vmf, ""}};
  for (const auto& t : gemm_tiles(device))
    out.push_back({"gemm_" + std::to_string(t.tm) + "x" + std::to_string(t.vw) + "x" + std::to_string(t.nv), gemm,
                   gemm_options(t.tm, t.vw, t.nv)});
  for (const auto& b : gemm_blocks(device))
    out.push_back({std::string(b.tf32 ? "gemm_tf32_" : "gemm_tiled_") + std::to_string(b.bm) + "x" +
                       std::to_string(b.bn) + "x" + std::to_string(b.bk) + "_" + std::to_string(b.wm) + "x" +
                       std::to_string(b.wn) + "_v" + std::to_string(b.vec) + "_s" + std::to_string(b.stages),
                   b.tf32 ? gemm_tf32 : gemm_tiled, gemm_tiled_options(b)});
  for (const unsigned f : {1u, 2u, 4u, 8u}) {
    out.push_back({"hashgrid_F" + std::to_string(f), hashgrid, hashgrid_options(f, false)});
    if (device.int64_atomics)
      out.push_back({"hashgrid_F" + std::to_string(f) + "_fixed", hashgrid, hashgrid_options(f, true)});
  }
  for (unsigned width = 16; width <= 64; width += 16)
    for (unsigned hidden = 1; hidden <= 4; ++hidden)
      for (unsigned outputs = 16; outputs <= 64; outputs += 16)
        if (mlp_fused_fits(width, hidden, outputs))
          out.push_back(
              {"mlp_fused_" + std::to_string(width) + "x" + std::to_string(hidden) + "_" + std::to_string(outputs),
               mlp_fused, mlp_fused_options(fused_inputs, width, hidden, outputs)});
  // The exchange builds both: int64 gradients need only the long type, not int64 atomics.
  out.push_back({"exchange_float", exchange, exchange_options(false)});
  out.push_back({"exchange_long", exchange, exchange_options(true)});
  return out;
}

}  // namespace clr::nn::programs
