#pragma once
// The processes of one job (docs/mpi.md). Under `mpirun` in a build with MPI (CLR_MPI) every process is one rank
// of MPI_COMM_WORLD; otherwise — no MPI in the build, or a plain launch — the job is this process alone, MPI is
// never initialised, and every collective below returns its input: a single process runs today's code path.
//
// Collectives must be called by every rank in the same order. A rank that fails calls finish() with its exit
// code, which aborts the whole job (MPI_Abort): the others may be waiting in a collective and would never return.
// A rank that stops answering (SIGSTOP, a hung node) must not hang the job either: a collective that has not
// completed after $CLRADIOSITY_MPI_TIMEOUT seconds (default 300; 0: wait forever) takes a roll call of the ranks —
// every rank answers while it waits in a collective — and fails naming the ranks that did not answer. A stop signal
// that finds a rank waiting ends the job within a second (StoppedWhileWaiting).
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.hpp"

namespace clr::distributed {

// Bad input that every rank finds at the same point (ranks given different work, a command that does not use MPI):
// the job can end without an abort, with rank 0's line alone.
class JobInputError : public InputError {
 public:
  using InputError::InputError;
};

// A stop signal (SIGINT, SIGTERM, …) reached this rank while it waited in a collective that the other ranks did not
// complete within a second: the job ends (exit 128 + the signal) with the work of its last safe point, a training's
// last checkpoint. Ranks that all take the signal mid-step complete their collectives within that second and stop
// together at the step's end instead.
class StoppedWhileWaiting : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

  // Before any work: every rank's `digest` of what it is about to compute (`what`: "the command line", "the scene
  // (its files)", …) must equal rank 0's. Otherwise every rank throws a JobInputError naming the first rank that
  // differs: ranks given other options would train one mixed model, or gather rows of different images.
  void require_same(const std::string& what, std::uint64_t digest) const;

  // Between pieces of a long computation outside any collective (a reference's passes), on the main thread: answers
  // the roll call of a rank that has waited past the timeout, so that a rank computing is taken for slow, not lost.
  void keep_alive() const;

  // Ends this process's part in the job: 0 finalises MPI; any other code aborts every rank with it (it does not
  // return then) unless every rank fails `together` at the same point (JobInputError): then each finalises and
  // returns the code. A single process just returns the code.
  int finish(int code, bool together = false);

 private:
  friend struct Collective;  // communicator_mpi.cpp: the MPI calls
  Communicator() = default;
  static Communicator make_world();
  // Completes a started non-blocking MPI operation (an MPI_Request*), answering roll calls and timing out
  // meanwhile; `what` names it in the timeout's message.
  void wait(void* mpi_request, const char* what) const;

  int rank_ = 0, size_ = 1, local_rank_ = 0;
  bool mpi_ = false;  // MPI initialised by this communicator
};

}  // namespace clr::distributed
