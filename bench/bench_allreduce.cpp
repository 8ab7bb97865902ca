// bench_allreduce: MPI_Allreduce time for the sizes of a training step's exchange (docs/mpi.md), beside the dense
// exchange it replaces. Run it as `mpirun -n 2 build/release/bench/bench_allreduce [SPARSE_KIB DENSE_KIB]`; the
// defaults are the Cornell box's measured bytes per step at batch 4096 (`train` prints them under mpirun).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "distributed/communicator.hpp"

namespace {

// Milliseconds per allreduce of `bytes`, best of five rounds of ten after a warm-up (the host is shared: the
// best round is the one least disturbed).
double allreduce_ms(const clr::distributed::Communicator& ranks, std::size_t bytes) {
  std::vector<std::int64_t> data(bytes / sizeof(std::int64_t), 1);
  ranks.sum(data);
  double best = 1e30;
  for (int round = 0; round < 5; ++round) {
    ranks.max(0);
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < 10; ++i) ranks.sum(data);
    // The slowest rank's time is the collective's.
    const double ms =
        ranks.max(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / 10);
    if (ms < best) best = ms;
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  auto& ranks = clr::distributed::Communicator::world();
  if (!ranks.distributed()) {
    std::puts("bench_allreduce: run it under mpirun with 2 or more ranks (and a build with MPI)");
    return ranks.finish(0);
  }
  const double sparse_kib = argc > 1 ? std::atof(argv[1]) : 7113.0, dense_kib = argc > 2 ? std::atof(argv[2]) : 43599.0;
  const struct {
    const char* what;
    double kib;
  } sizes[] = {{"N-Module MLP gradient (width 256)", 213507 * 4 / 1024.0},
               {"sparse step exchange", sparse_kib},
               {"dense step exchange", dense_kib}};
  for (const auto& s : sizes) {
    const auto bytes = std::size_t(s.kib * 1024.0);
    const double ms = allreduce_ms(ranks, bytes);
    if (ranks.rank() == 0)
      std::printf("%-36s %10.1f KiB  %8.3f ms  %6.2f GB/s (algorithm bandwidth)\n", s.what, s.kib, ms,
                  double(bytes) / (ms * 1e-3) * 1e-9);
  }
  return ranks.finish(0);
}
