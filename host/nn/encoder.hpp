#pragma once
// The input encoding of a network, composed of optional parts read from one raw input row per point:
//   columns 0-2 position x, 3-5 outgoing direction ω_o, 6-8 normal n, 9-11 albedo, 12 roughness  (kRawInputs = 13)
// Parts, in this order in the encoded row: hash grid of x (normalised to the scene's bounding box),
// SH (16) of ω_o, SH (16) of n, raw albedo (3), raw roughness (1). Only the hash grid is trainable.
#include <optional>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"
#include "nn/hashgrid.hpp"

namespace clr::nn {

namespace raw {
inline constexpr std::size_t kPosition = 0, kDirection = 3, kNormal = 6, kAlbedo = 9, kRoughness = 12;
}
inline constexpr std::size_t kRawInputs = 13;

struct EncoderConfig {
  std::optional<HashGridConfig> grid = HashGridConfig{};
  bool sh_direction = true;
  bool sh_normal = true;
  bool albedo = true;
  bool roughness = false;
};

class Encoder {
 public:
  Encoder(cl::Context& ctx, EncoderConfig config, AdamConfig grid_adam, std::uint64_t seed);

  const EncoderConfig& config() const { return config_; }
  std::size_t outputs() const { return outputs_; }
  HashGrid* grid() { return grid_ ? &*grid_ : nullptr; }
  const HashGrid* grid() const { return grid_ ? &*grid_ : nullptr; }

  // raw rows [row0, row0 + rows) of a [· × kRawInputs] buffer → encoded [rows × outputs()] (packed, from row 0).
  void forward(const cl::Buffer<float>& raw, std::size_t row0, std::size_t rows, cl::Buffer<float>& encoded);
  // dL/dencoded [rows × outputs()] → dL/dtable of the hash grid (the other parts have no parameters).
  void backward(const cl::Buffer<float>& raw, std::size_t row0, std::size_t rows, const cl::Buffer<float>& d_encoded);
  void set_learning_rate_scale(float s) {
    if (grid_) grid_->adam().set_learning_rate_scale(s);
  }
  void adam_step() {
    if (grid_) grid_->adam_step();
  }

 private:
  cl::Context* ctx_;
  EncoderConfig config_;
  std::optional<HashGrid> grid_;
  std::size_t outputs_ = 0;
  cl::Kernel sh_, copy_;
};

}  // namespace clr::nn
