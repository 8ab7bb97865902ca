#pragma once
// Data-parallel training's one exchange (docs/mpi.md): between a network's backward and its adam_step, every
// rank's gradient becomes the sum over the ranks. Each rank's loss is normalised by the global batch, so the sum is
// the gradient of the global batch's mean, and every rank then takes the same Adam step from the same parameters.
//
// The MLP's gradient is dense and small (a few hundred thousand floats): one MPI_Allreduce. The hash table's is
// large and mostly zero — a step reaches at most points · 8 entries a level of 2^14..2^18 — so the ranks first
// OR a bitmap of the entries they touched (one bit an entry), then sum only the union's rows, packed on the device.
// The union also becomes every rank's touched set, so lazy Adam updates the same entries everywhere. The
// fixed-point gradient (the hash grid's deterministic mode) sums as int64: exact, so the table's gradient equals
// the one-process gradient bit for bit.
//
// With one process every call returns at once, and no kernel is built.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"
#include "distributed/communicator.hpp"
#include "nn/network.hpp"

namespace clr::distributed {

struct ExchangeStats {
  std::uint64_t exchanges = 0;    // reduce() calls
  std::uint64_t bytes = 0;        // sent by this rank into allreduces (each element once)
  std::uint64_t dense_bytes = 0;  // what a dense exchange of the same gradients would have sent
  double wait_seconds = 0;        // for the slowest rank to finish its backward (load imbalance)
  double allreduce_seconds = 0;   // inside the allreduces, after every rank arrived
  double total_seconds = 0;       // reduce() after the device finished the backward: reads, packing, MPI, writes
};

class GradientExchange {
 public:
  GradientExchange(cl::Context& ctx, const Communicator& comm);

  const Communicator& communicator() const { return *comm_; }
  // Sums `net`'s accumulated gradient over the ranks, in place; a no-op for one process.
  void reduce(nn::Network& net);
  // Throws naming this rank, `what` and `step` when `net`'s parameters differ from rank 0's (checksums compared):
  // the ranks would go on training different models.
  void check_same_parameters(const nn::Network& net, const std::string& what, std::uint64_t step) const;
  const ExchangeStats& stats() const { return stats_; }

 private:
  struct Kernels {
    cl::Kernel bits, gather_float, scatter_float, gather_fixed, scatter_fixed;
  };
  template <typename G>
  void reduce_rows(cl::Buffer<G>& grad, cl::Kernel& gather, cl::Kernel& scatter, std::size_t features,
                   cl::Buffer<std::uint8_t>& touched);

  cl::Context* ctx_;
  const Communicator* comm_;
  std::optional<Kernels> kernels_;
  ExchangeStats stats_;
  std::vector<float> dense_host_;
  std::vector<std::uint32_t> bits_host_, rows_host_;
  std::vector<float> packed_float_host_;
  std::vector<std::int64_t> packed_fixed_host_;
  cl::Buffer<std::uint32_t> bits_, rows_;
  cl::Buffer<float> packed_float_;
  cl::Buffer<std::int64_t> packed_fixed_;
};

}  // namespace clr::distributed
