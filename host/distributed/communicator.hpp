#pragma once
// The processes of one job (docs/mpi.md). Under `mpirun` in a build with MPI (CLR_MPI) every process is one rank
// of MPI_COMM_WORLD; otherwise — no MPI in the build, or a plain launch — the job is this process alone, MPI is
// never initialised, and every collective below returns its input: a single process runs today's code path.
//
// Collectives must be called by every rank in the same order. A rank that fails calls finish() with its exit
// code, which aborts the whole job (MPI_Abort): the others may be waiting in a collective and would never return.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace clr::distributed {

class Communicator {
 public:
  // The job this process belongs to; initialises MPI on first use when launched by mpirun.
  static Communicator& world();
  // A job of one process whatever the launch (tests compare against it).
  static Communicator& single();

  int rank() const { return rank_; }
  int size() const { return size_; }
  // This rank's index among the ranks on its machine (devices are shared out by it).
  int local_rank() const { return local_rank_; }
  bool distributed() const { return size_ > 1; }

  // In place, element-wise over all ranks. Integer sums are exact, so fixed-point gradients stay bit-reproducible.
  void sum(std::span<float> values) const;
  void sum(std::span<double> values) const;
  void sum(std::span<std::int64_t> values) const;
  void bitwise_or(std::span<std::uint32_t> values) const;
  double max(double value) const;
  // Rank 0's bytes on every rank.
  void broadcast(std::string& bytes) const;
  void broadcast(std::span<std::uint64_t> values) const;
  void broadcast(std::span<float> values) const;
  // Rank 0 receives every rank's `part` concatenated in rank order; the other ranks receive nothing.
  std::vector<float> gather(std::span<const float> part) const;

  // Ends this process's part in the job: 0 finalises MPI; any other code aborts every rank with it (it does not
  // return then). A single process just returns the code.
  int finish(int code);

 private:
  Communicator() = default;
  static Communicator make_world();

  int rank_ = 0, size_ = 1, local_rank_ = 0;
  bool mpi_ = false;  // MPI initialised by this communicator
};

}  // namespace clr::distributed
