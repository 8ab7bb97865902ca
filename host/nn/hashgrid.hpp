#pragma once
// Multiresolution hash-grid encoding of a 3-D position (kernels/hashgrid.cl): levels × features outputs.
// The table is trainable: backward accumulates dL/dtable (CAS atomics) and flags the entries a batch reached,
// and adam_step() updates only those (lazy Adam, kernels/adam.cl): the dense gradient + Adam pass over a big
// table is memory-bound on a CPU (docs/design.md §6), while a batch touches at most rows · 8 entries per level.
#include <array>
#include <cstdint>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"
#include "nn/adam.hpp"

namespace clr::nn {

struct HashGridConfig {
  std::size_t levels = 12;
  std::size_t features = 2;     // per level: 1, 2, 4 or 8
  std::size_t log2_table = 18;  // T = 2^log2_table entries per level at most
  std::size_t base_resolution = 16;
  double growth = 1.5;                                      // b: N_l = floor(N_min · b^l)
  std::array<float, 3> bbox_lo{0, 0, 0}, bbox_hi{1, 1, 1};  // positions are normalised to this box, then clamped
  // Accumulate the table gradient in int64 fixed point (kernels/hashgrid.cl) so a step is bit-reproducible;
  // falls back to float CAS atomics on devices without cl_khr_int64_base_atomics.
  bool deterministic = true;
  // Adam over every entry at every step (PyTorch's dense Adam, the Neural Radiosity authors' code): an entry the
  // batch did not reach keeps moving on its momentum. false: only the entries reached (lazy), which is what a CPU
  // can afford for big tables (docs/design.md §6); docs/method.md measures the two.
  bool dense_adam = false;
  // The table's Adam learning rate as a multiple of the network's (adam.learning_rate; schedules scale both alike).
  // An entry moves only on the steps whose batch reaches it, so at the MLP's rate the table localises slowly: on
  // Veach Ajar the dark room borrowed the bright one's radiance for ~200 steps (docs/method.md, "The start and the
  // swings").
  float learning_rate_factor = 1.0f;
};

struct HashGridLevel {
  std::uint32_t resolution;  // N_l cells per axis
  bool dense;                // (N_l + 1)³ ≤ T: one entry per vertex, no hashing
  std::uint32_t offset;      // first entry of this level in the table
  std::uint32_t entries;     // (N_l + 1)³ when dense, else T
};

// The level layout of a config (also the host twin's).
std::vector<HashGridLevel> hashgrid_levels(const HashGridConfig& config);

class HashGrid {
 public:
  HashGrid(cl::Context& ctx, HashGridConfig config, AdamConfig adam, std::uint64_t seed);

  const HashGridConfig& config() const { return config_; }
  const std::vector<HashGridLevel>& levels() const { return levels_; }
  std::size_t outputs() const { return config_.levels * config_.features; }
  std::size_t entries() const { return touched_.size(); }

  // positions: rows × 3 at in[in_off + r·in_ld]; writes out[out_off + r·out_ld + l·F + f].
  void forward(const cl::Buffer<float>& in, std::size_t in_off, std::size_t in_ld, std::size_t rows,
               cl::Buffer<float>& out, std::size_t out_off, std::size_t out_ld);
  // Accumulates dL/dtable from d_out (same addressing as forward's output).
  void backward(const cl::Buffer<float>& in, std::size_t in_off, std::size_t in_ld, std::size_t rows,
                const cl::Buffer<float>& d_out, std::size_t d_off, std::size_t d_ld);
  void adam_step();

  cl::Buffer<float>& params() { return table_; }
  // dL/dtable as floats (converted from fixed point in the deterministic mode), and its reset.
  std::vector<float> gradient() const;
  void clear_gradient();
  bool fixed_point_gradient() const { return fixed_; }
  // The raw gradient buffer of the mode in use (the other is empty): what MPI ranks sum (distributed/).
  cl::Buffer<float>& float_gradient() { return grad_; }
  cl::Buffer<std::int64_t>& fixed_gradient() { return grad_fixed_; }
  cl::Buffer<std::uint8_t>& touched() { return touched_; }
  Adam& adam() { return adam_; }
  const cl::Buffer<float>& params() const { return table_; }
  const Adam& adam() const { return adam_; }

 private:
  std::array<float, 3> inverse_extent() const;

  cl::Context* ctx_;
  HashGridConfig config_;
  std::vector<HashGridLevel> levels_;
  cl::Buffer<cl_uint4> level_info_;
  bool fixed_ = false;
  cl::Buffer<float> table_, grad_;       // grad_ holds the float gradient, or is empty in fixed-point mode
  cl::Buffer<std::int64_t> grad_fixed_;  // the fixed-point gradient, or empty
  cl::Buffer<std::uint8_t> touched_;
  Adam adam_;
  cl::Kernel forward_, backward_;
};

}  // namespace clr::nn
