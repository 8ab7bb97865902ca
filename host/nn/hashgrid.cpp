#include "nn/hashgrid.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

#include "common/error.hpp"
#include "nn/gemm.hpp"
#include "nn/programs.hpp"

namespace clr::nn {
namespace {

bool use_fixed(const cl::Context& ctx, const HashGridConfig& c) {
  return c.deterministic && ctx.device().int64_atomics;
}

std::string options(const cl::Context& ctx, const HashGridConfig& c) {
  return programs::hashgrid_options(unsigned(c.features), use_fixed(ctx, c));
}

std::size_t table_entries(const HashGridConfig& c) {
  std::size_t n = 0;
  for (const auto& l : hashgrid_levels(c)) n += l.entries;
  return n;
}

AdamConfig scaled(AdamConfig adam, float factor) {
  adam.learning_rate *= factor;
  return adam;
}

}  // namespace

std::vector<HashGridLevel> hashgrid_levels(const HashGridConfig& c) {
  if (c.levels == 0 || c.levels > 32) throw InputError("hash grid: levels must be in 1..32");
  if (c.features != 1 && c.features != 2 && c.features != 4 && c.features != 8)
    throw InputError("hash grid: features per level must be 1, 2, 4 or 8");
  if (c.log2_table < 4 || c.log2_table > 26) throw InputError("hash grid: log2 table size must be in 4..26");
  // Negated so that a NaN growth fails too.
  if (!(c.base_resolution >= 1 && c.growth >= 1.0)) throw InputError("hash grid: base resolution ≥ 1 and growth ≥ 1");
  const std::uint64_t T = std::uint64_t(1) << c.log2_table;
  std::vector<HashGridLevel> out;
  std::uint64_t offset = 0;
  for (std::size_t l = 0; l < c.levels; ++l) {
    const double r = std::floor(double(c.base_resolution) * std::pow(c.growth, double(l)));
    if (r > 1e6) throw InputError("hash grid: level " + std::to_string(l) + " resolution exceeds 10^6");
    const auto res = std::uint64_t(r);
    const std::uint64_t dense_entries = (res + 1) * (res + 1) * (res + 1);
    const bool dense = dense_entries <= T;
    const std::uint64_t entries = dense ? dense_entries : T;
    out.push_back({std::uint32_t(res), dense, std::uint32_t(offset), std::uint32_t(entries)});
    offset += entries;
    if (offset * c.features > 0xffffffffu) throw InputError("hash grid: table exceeds 2^32 floats");
  }
  return out;
}

HashGrid::HashGrid(cl::Context& ctx, HashGridConfig config, AdamConfig adam, std::uint64_t seed)
    : ctx_(&ctx),
      config_(config),
      levels_(hashgrid_levels(config)),
      level_info_(ctx, levels_.size()),
      fixed_(use_fixed(ctx, config)),
      table_(ctx, table_entries(config) * config.features),
      grad_(ctx, fixed_ ? 0 : table_.size()),
      grad_fixed_(ctx, fixed_ ? table_.size() : 0),
      touched_(ctx, table_entries(config)),
      adam_(ctx, table_.size(), scaled(adam, config.learning_rate_factor)),
      forward_(ctx.program(programs::hashgrid, options(ctx, config)).kernel("hashgrid_forward")),
      backward_(ctx.program(programs::hashgrid, options(ctx, config)).kernel("hashgrid_backward")) {
  std::vector<cl_uint4> info(levels_.size());
  for (std::size_t l = 0; l < levels_.size(); ++l)
    info[l] = cl_uint4{{levels_[l].resolution, levels_[l].dense ? 1u : 0u, levels_[l].offset, levels_[l].entries}};
  level_info_.write(info);
  // instant-ngp's initialisation: small uniform values, so the network starts from near-zero features.
  std::vector<float> host(table_.size());
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1e-4f, 1e-4f);
  for (auto& v : host) v = u(rng);
  table_.write(host);
  clear_gradient();
  touched_.fill(std::uint8_t(0));
}

void HashGrid::clear_gradient() {
  if (fixed_)
    grad_fixed_.fill(std::int64_t(0));
  else
    grad_.fill(0.0f);
}

std::vector<float> HashGrid::gradient() const {
  if (!fixed_) return grad_.read();
  const auto raw = grad_fixed_.read();
  std::vector<float> out(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) out[i] = float(double(raw[i]) * 0x1p-40);
  return out;
}

void HashGrid::adam_step() {
  if (config_.dense_adam) touched_.fill(std::uint8_t(1));  // the gradient of an entry not reached is 0
  if (fixed_)
    adam_.step_sparse_fixed(table_, grad_fixed_, touched_, config_.features);
  else
    adam_.step_sparse(table_, grad_, touched_, config_.features);
}

std::array<float, 3> HashGrid::inverse_extent() const {
  std::array<float, 3> inv{};
  for (std::size_t i = 0; i < 3; ++i) {
    const float extent = config_.bbox_hi[i] - config_.bbox_lo[i];
    if (!(extent > 0.0f)) throw InputError("hash grid: the bounding box is empty along axis " + std::to_string(i));
    inv[i] = 1.0f / extent;
  }
  return inv;
}

void HashGrid::forward(const cl::Buffer<float>& in, std::size_t in_off, std::size_t in_ld, std::size_t rows,
                       cl::Buffer<float>& out, std::size_t out_off, std::size_t out_ld) {
  const auto inv = inverse_extent();
  const auto& lo = config_.bbox_lo;
  forward_
      .args(u32(rows), u32(levels_.size()), in, u32(in_off), u32(in_ld), lo[0], lo[1], lo[2], inv[0], inv[1], inv[2],
            level_info_, table_, out, u32(out_off), u32(out_ld))
      .launch({rows, levels_.size()}, {64, 1});
}

void HashGrid::backward(const cl::Buffer<float>& in, std::size_t in_off, std::size_t in_ld, std::size_t rows,
                        const cl::Buffer<float>& d_out, std::size_t d_off, std::size_t d_ld) {
  const auto inv = inverse_extent();
  const auto& lo = config_.bbox_lo;
  auto launch = [&](const auto& grad) {
    backward_
        .args(u32(rows), u32(levels_.size()), in, u32(in_off), u32(in_ld), lo[0], lo[1], lo[2], inv[0], inv[1], inv[2],
              level_info_, d_out, u32(d_off), u32(d_ld), grad, touched_)
        .launch({rows, levels_.size()}, {64, 1});
  };
  if (fixed_)
    launch(grad_fixed_);
  else
    launch(grad_);
}

}  // namespace clr::nn
