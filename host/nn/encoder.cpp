#include "nn/encoder.hpp"

#include <tuple>
#include <utility>

#include "common/error.hpp"
#include "nn/gemm.hpp"
#include "nn/programs.hpp"

namespace clr::nn {

Encoder::Encoder(cl::Context& ctx, EncoderConfig config, AdamConfig grid_adam, std::uint64_t seed)
    : ctx_(&ctx),
      config_(config),
      sh_(ctx.program(programs::sh).kernel("sh_forward")),
      copy_(ctx.program(programs::sh).kernel("copy_columns")) {
  if (config_.grid) grid_.emplace(ctx, *config_.grid, grid_adam, seed);
  outputs_ = (grid_ ? grid_->outputs() : 0) + (config_.sh_direction ? 16 : 0) + (config_.sh_normal ? 16 : 0) +
             (config_.albedo ? 3 : 0) + (config_.roughness ? 1 : 0);
  if (outputs_ == 0) throw InputError("encoder: no input part is enabled");
}

void Encoder::forward(const cl::Buffer<float>& raw, std::size_t row0, std::size_t rows, cl::Buffer<float>& encoded) {
  const std::size_t D = outputs_, base = row0 * kRawInputs;
  std::size_t col = 0;
  if (grid_) {
    grid_->forward(raw, base + raw::kPosition, kRawInputs, rows, encoded, col, D);
    col += grid_->outputs();
  }
  for (auto [on, src] :
       {std::pair{config_.sh_direction, raw::kDirection}, std::pair{config_.sh_normal, raw::kNormal}}) {
    if (!on) continue;
    sh_.args(u32(rows), raw, u32(base + src), u32(kRawInputs), encoded, u32(col), u32(D)).launch(rows, 64);
    col += 16;
  }
  for (auto [on, src, n] : {std::tuple{config_.albedo, raw::kAlbedo, std::size_t(3)},
                            std::tuple{config_.roughness, raw::kRoughness, std::size_t(1)}}) {
    if (!on) continue;
    copy_.args(u32(rows), u32(n), raw, u32(base + src), u32(kRawInputs), encoded, u32(col), u32(D))
        .launch({n, rows}, {1, 64});
    col += n;
  }
}

void Encoder::backward(const cl::Buffer<float>& raw, std::size_t row0, std::size_t rows,
                       const cl::Buffer<float>& d_encoded) {
  if (grid_) grid_->backward(raw, row0 * kRawInputs + raw::kPosition, kRawInputs, rows, d_encoded, 0, outputs_);
}

}  // namespace clr::nn
