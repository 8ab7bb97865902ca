#include "distributed/gradient_exchange.hpp"

#include <bit>
#include <chrono>
#include <stdexcept>

#include "nn/checkpoint.hpp"
#include "nn/programs.hpp"

namespace clr::distributed {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::uint32_t u32(std::size_t v) { return std::uint32_t(v); }

}  // namespace

GradientExchange::GradientExchange(cl::Context& ctx, const Communicator& comm) : ctx_(&ctx), comm_(&comm) {
  if (!comm.distributed()) return;
  const auto& f = ctx.program(nn::programs::exchange, nn::programs::exchange_options(false));
  const auto& l = ctx.program(nn::programs::exchange, nn::programs::exchange_options(true));
  kernels_.emplace(Kernels{f.kernel("touched_bits"), f.kernel("gather_rows"), f.kernel("scatter_rows"),
                           l.kernel("gather_rows"), l.kernel("scatter_rows")});
}

void GradientExchange::reduce(nn::Network& net) {
  if (!comm_->distributed()) return;
  // The backward's kernels are still queued: their time is the step's compute, not the exchange's.
  ctx_->finish();
  // Waiting for the slowest rank is load imbalance, not transfer: timed apart, so the allreduce time is the wire's.
  const auto arrived = Clock::now();
  comm_->max(0.0);
  stats_.wait_seconds += seconds_since(arrived);
  const auto start = Clock::now();
  auto& grads = net.mlp().grads();
  dense_host_.resize(grads.size());
  grads.read(dense_host_);
  const auto in_mpi = Clock::now();
  comm_->sum(dense_host_);
  stats_.allreduce_seconds += seconds_since(in_mpi);
  grads.write(dense_host_);
  stats_.bytes += dense_host_.size() * sizeof(float);
  stats_.dense_bytes += dense_host_.size() * sizeof(float);

  if (nn::HashGrid* grid = net.encoder().grid()) {
    const std::size_t F = grid->config().features;
    if (grid->fixed_point_gradient()) {
      reduce_rows(grid->fixed_gradient(), kernels_->gather_fixed, kernels_->scatter_fixed, F, grid->touched());
      stats_.dense_bytes += grid->fixed_gradient().bytes();
    } else {
      reduce_rows(grid->float_gradient(), kernels_->gather_float, kernels_->scatter_float, F, grid->touched());
      stats_.dense_bytes += grid->float_gradient().bytes();
    }
  }
  ++stats_.exchanges;
  stats_.total_seconds += seconds_since(start);
}

template <typename G>
void GradientExchange::reduce_rows(cl::Buffer<G>& grad, cl::Kernel& gather, cl::Kernel& scatter, std::size_t features,
                                   cl::Buffer<std::uint8_t>& touched) {
  // The union of the touched entries: a bitmap OR over the ranks.
  const std::size_t entries = touched.size(), words = (entries + 31) / 32;
  cl::reserve(*ctx_, bits_, words);
  kernels_->bits.args(u32(entries), touched, bits_).launch(words);
  bits_host_.resize(words);
  bits_.read(std::span<std::uint32_t>(bits_host_.data(), words));
  auto t = Clock::now();
  comm_->bitwise_or(bits_host_);
  stats_.allreduce_seconds += seconds_since(t);
  stats_.bytes += words * sizeof(std::uint32_t);

  rows_host_.clear();
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint32_t word = bits_host_[w]; word; word &= word - 1)
      rows_host_.push_back(u32(32 * w + std::size_t(std::countr_zero(word))));
  const std::size_t rows = rows_host_.size();
  if (rows == 0) return;
  cl::upload(*ctx_, rows_, rows_host_);

  // Only the union's rows travel; the packed sums go back to the same rows, which join the touched set.
  auto& packed = [&]() -> cl::Buffer<G>& {
    if constexpr (std::is_same_v<G, float>)
      return packed_float_;
    else
      return packed_fixed_;
  }();
  auto& host = [&]() -> std::vector<G>& {
    if constexpr (std::is_same_v<G, float>)
      return packed_float_host_;
    else
      return packed_fixed_host_;
  }();
  cl::reserve(*ctx_, packed, rows * features);
  gather.args(u32(rows), u32(features), rows_, grad, packed).launch(rows);
  host.resize(rows * features);
  packed.read(std::span<G>(host.data(), host.size()));
  t = Clock::now();
  comm_->sum(host);
  stats_.allreduce_seconds += seconds_since(t);
  stats_.bytes += host.size() * sizeof(G);
  packed.write(host);
  scatter.args(u32(rows), u32(features), rows_, packed, grad, touched).launch(rows);
}

void GradientExchange::check_same_parameters(const nn::Network& net, const std::string& what,
                                             std::uint64_t step) const {
  if (!comm_->distributed()) return;
  const auto params = net.mlp().params().read();
  std::uint64_t sums[2] = {nn::fnv1a64(params.data(), params.size() * sizeof(float)), 0};
  if (const nn::HashGrid* grid = net.encoder().grid()) {
    const auto table = grid->params().read();
    sums[1] = nn::fnv1a64(table.data(), table.size() * sizeof(float));
  }
  std::uint64_t reference[2] = {sums[0], sums[1]};
  comm_->broadcast(reference);
  if (reference[0] != sums[0] || reference[1] != sums[1])
    throw std::runtime_error("rank " + std::to_string(comm_->rank()) + ": the " + what +
                             "'s parameters differ from rank 0's after step " + std::to_string(step) +
                             " (checksums compared): the ranks no longer train one model");
}

}  // namespace clr::distributed
