// The communicator over MPI (built when CLR_MPI is on): MPI_COMM_WORLD of the launching mpirun.
#include <mpi.h>

#include <climits>
#include <cstdlib>
#include <stdexcept>

#include "distributed/communicator.hpp"

namespace clr::distributed {
namespace {

// Set by the launchers of Open MPI, MPICH/Hydra and PMIx: without them this process was started alone, and MPI
// stays uninitialised (a singleton MPI_Init would cost start-up time and change nothing).
bool launched_by_mpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(var)) return true;
  return false;
}

int count_of(std::size_t n) {
  if (n > std::size_t(INT_MAX)) throw std::runtime_error("MPI message of " + std::to_string(n) + " elements");
  return int(n);
}

}  // namespace

Communicator Communicator::make_world() {
  Communicator c;
  if (!launched_by_mpirun()) return c;
  int provided = 0;
  // Only the main thread calls MPI; the worker threads (parallel_for, PoCL) never do.
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  c.mpi_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &c.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &c.size_);
  if (const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_RANK")) {
    c.local_rank_ = std::atoi(local);
  } else {
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, c.rank_, MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &c.local_rank_);
    MPI_Comm_free(&node);
  }
  return c;
}

Communicator& Communicator::world() {
  static Communicator world = make_world();
  return world;
}

Communicator& Communicator::single() {
  static Communicator one;
  return one;
}

void Communicator::sum(std::span<float> v) const {
  if (distributed()) MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_FLOAT, MPI_SUM, MPI_COMM_WORLD);
}

void Communicator::sum(std::span<double> v) const {
  if (distributed()) MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
}

void Communicator::sum(std::span<std::int64_t> v) const {
  if (distributed()) MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
}

void Communicator::bitwise_or(std::span<std::uint32_t> v) const {
  if (distributed()) MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_UINT32_T, MPI_BOR, MPI_COMM_WORLD);
}

double Communicator::max(double value) const {
  if (distributed()) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

void Communicator::broadcast(std::string& bytes) const {
  if (!distributed()) return;
  std::uint64_t n = bytes.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  bytes.resize(n);
  MPI_Bcast(bytes.data(), count_of(n), MPI_CHAR, 0, MPI_COMM_WORLD);
}

void Communicator::broadcast(std::span<std::uint64_t> v) const {
  if (distributed()) MPI_Bcast(v.data(), count_of(v.size()), MPI_UINT64_T, 0, MPI_COMM_WORLD);
}

void Communicator::broadcast(std::span<float> v) const {
  if (distributed()) MPI_Bcast(v.data(), count_of(v.size()), MPI_FLOAT, 0, MPI_COMM_WORLD);
}

std::vector<float> Communicator::gather(std::span<const float> part) const {
  if (!distributed()) return {part.begin(), part.end()};
  const int mine = count_of(part.size());
  std::vector<int> counts(rank_ == 0 ? std::size_t(size_) : 0), offsets;
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<float> all;
  if (rank_ == 0) {
    std::size_t total = 0;
    for (const int c : counts) {
      offsets.push_back(count_of(total));
      total += std::size_t(c);
    }
    all.resize(total);
  }
  MPI_Gatherv(part.data(), mine, MPI_FLOAT, all.data(), counts.data(), offsets.data(), MPI_FLOAT, 0, MPI_COMM_WORLD);
  return all;
}

int Communicator::finish(int code) {
  if (!mpi_) return code;
  // Peers of a failed rank may be blocked in a collective that will never complete: only an abort ends them.
  if (code != 0 && distributed()) MPI_Abort(MPI_COMM_WORLD, code);
  MPI_Finalize();
  mpi_ = false;
  return code;
}

}  // namespace clr::distributed
