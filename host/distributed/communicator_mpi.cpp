// The communicator over MPI (built when CLR_MPI is on): MPI_COMM_WORLD of the launching mpirun.
#include <mpi.h>

#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "common/input_file.hpp"
#include "common/stop_signal.hpp"
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

// The roll call's messages: point to point, so they pass beside any collective in progress. An answer says where
// the rank is: waiting in a collective, or computing outside any (Communicator::keep_alive).
constexpr int kRollCallTag = 0x5e11, kPresentTag = 0x5e12;
constexpr int kWaiting = 1, kComputing = 2;
constexpr int kAnswerSeconds = 30;

// $CLRADIOSITY_MPI_TIMEOUT, read by the first collective (the command lines' comparison, before any work). Every
// rank reads the same value, so a bad one is a JobInputError: the job ends with rank 0's line alone. Below a second
// a rank that is merely a moment behind would be taken for a lost one (the roll call itself waits seconds).
double collective_timeout() {
  const char* text = std::getenv("CLRADIOSITY_MPI_TIMEOUT");
  if (!text || !*text) return 300;
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(seconds) || seconds < 0 || (seconds > 0 && seconds < 1))
    throw JobInputError(std::string("CLRADIOSITY_MPI_TIMEOUT '") + clip(text) +
                        "': give seconds, 0 (no timeout) or at least 1");
  return seconds;
}

// How long a rank that a stop signal reached waits on for the collective it is in: ranks that all took the signal
// mid-step arrive within it (and stop together at the step's end); a rank still missing after it is not waited for.
constexpr double kStopGraceSeconds = 1.0;

// Throws StoppedWhileWaiting once a stop signal has been pending for the grace period while this rank waits.
class StopWatch {
 public:
  explicit StopWatch(const char* what) : what_(what) {}
  void check() {
    if (!stop_requested()) return;
    const auto now = std::chrono::steady_clock::now();
    if (!seen_) {
      seen_ = true;
      since_ = now;
    } else if (std::chrono::duration<double>(now - since_).count() > kStopGraceSeconds) {
      const char* name = sigabbrev_np(stop_signal());
      throw StoppedWhileWaiting(std::string("stopped by ") + (name ? std::string("SIG") + name : "a stop request") +
                                " while waiting in " + what_ +
                                ": the other ranks did not arrive within 1 s (ending the job; a training keeps its "
                                "last checkpoint)");
    }
  }

 private:
  const char* what_;
  bool seen_ = false;
  std::chrono::steady_clock::time_point since_;
};

// Answers every roll call that has arrived: this rank is here, in `state`.
void answer_roll_calls(int state = kWaiting) {
  for (;;) {
    int pending = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kRollCallTag, MPI_COMM_WORLD, &pending, &status);
    if (!pending) return;
    int token = 0;
    MPI_Recv(&token, 1, MPI_INT, status.MPI_SOURCE, kRollCallTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    MPI_Send(&state, 1, MPI_INT, status.MPI_SOURCE, kPresentTag, MPI_COMM_WORLD);  // 4 bytes: sent eagerly
  }
}

// After the timeout: asks every other rank whether it is waiting too, gives them a few seconds to answer, and
// fails naming the ones that did not (or, when all did, the mismatch of collectives that left them all waiting).
// Returns where a rank answered that it is still computing, or where the collective itself (`request`) completed
// meanwhile (its last rank arrived and answered as waiting): the job is slow, not stuck, and the wait goes on.
void roll_call(MPI_Request& request, int rank, int size, const char* what, double timeout, StopWatch& stop) {
  int token = 1;
  std::vector<MPI_Request> asked;
  for (int r = 0; r < size; ++r)
    if (r != rank) MPI_Isend(&token, 1, MPI_INT, r, kRollCallTag, MPI_COMM_WORLD, &asked.emplace_back());
  std::vector<bool> present(std::size_t(size), false);
  present[std::size_t(rank)] = true;
  int answers = 1;
  bool computing = false;
  // Long enough for a computing rank to finish the piece of work it is in (a reference's pass takes seconds).
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(kAnswerSeconds);
  const auto completed = [&] {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    return done != 0;
  };
  while (answers < size && std::chrono::steady_clock::now() < until) {
    if (completed()) return;
    stop.check();
    answer_roll_calls();
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kPresentTag, MPI_COMM_WORLD, &arrived, &status);
    if (!arrived) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    MPI_Recv(&token, 1, MPI_INT, status.MPI_SOURCE, kPresentTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    computing = computing || token == kComputing;
    if (!present[std::size_t(status.MPI_SOURCE)]) ++answers;
    present[std::size_t(status.MPI_SOURCE)] = true;
  }
  // A rank that computes answers between its pieces of work; the others' answers may still be on their way, and are
  // read (and dropped) with the next roll call's.
  if (computing || completed()) return;
  std::string silent;
  for (int r = 0; r < size; ++r)
    if (!present[std::size_t(r)]) silent += (silent.empty() ? "" : ", ") + std::to_string(r);
  char limit[64];
  std::snprintf(limit, sizeof limit, "%g s", timeout);
  // The requests of unanswered roll calls stay pending: the job ends now.
  if (silent.empty())
    throw std::runtime_error(std::string(what) + " did not complete within " + limit +
                             " although every rank is waiting: the ranks are in different collectives (ending the "
                             "job; CLRADIOSITY_MPI_TIMEOUT sets the limit)");
  throw std::runtime_error(std::string(what) + " did not complete within " + limit + ": rank" +
                           (silent.find(',') == std::string::npos ? " " : "s ") + silent + " did not answer within " +
                           std::to_string(kAnswerSeconds) +
                           " s: stopped, hung or lost (a rank computing outside any "
                           "collective answers between its pieces of work; ending the job; CLRADIOSITY_MPI_TIMEOUT "
                           "sets the limit, 0 waits for good)");
}

}  // namespace

// Every collective is started non-blocking and completed here: polling lets this rank answer roll calls while it
// waits, and lets it give up after the timeout. A pause of this process (SIGSTOP of the whole job, Ctrl-Z) restarts
// the clock rather than counting as the others' silence.
void Communicator::wait(void* pending, const char* what) const {
  auto& request = *static_cast<MPI_Request*>(pending);
  // A bad value is refused only once this collective is complete: MPI would otherwise go on writing into buffers
  // the exception frees (heap corruption, then an abort in MPI_Finalize). Every rank reads the same value, so all
  // of them complete it and fail here together.
  static const double timeout = [&] {
    try {
      return collective_timeout();
    } catch (const JobInputError&) {
      MPI_Wait(&request, MPI_STATUS_IGNORE);
      throw;
    }
  }();
  auto start = std::chrono::steady_clock::now();
  unsigned continued = continue_count();
  StopWatch stop(what);
  for (long polls = 0;; ++polls) {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    stop.check();
    answer_roll_calls();
    const auto now = std::chrono::steady_clock::now();
    if (continue_count() != continued) {
      continued = continue_count();
      start = now;
    }
    if (timeout > 0 && std::chrono::duration<double>(now - start).count() > timeout) {
      roll_call(request, rank_, size_, what, timeout, stop);
      start = std::chrono::steady_clock::now();  // slow, not stuck: the next poll sees a completed collective
    }
    // Spin briefly (a step's collectives usually complete within microseconds), then yield the core to the
    // device's threads.
    if (polls > 2000) std::this_thread::sleep_for(std::chrono::microseconds(polls > 200000 ? 1000 : 50));
  }
}

void Communicator::keep_alive() const {
  if (mpi_) answer_roll_calls(kComputing);
}

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

struct Collective {
  static void allreduce(const Communicator& c, void* data, std::size_t n, MPI_Datatype type, MPI_Op op) {
    MPI_Request r;
    MPI_Iallreduce(MPI_IN_PLACE, data, count_of(n), type, op, MPI_COMM_WORLD, &r);
    c.wait(&r, "an MPI allreduce");
  }
  static void broadcast(const Communicator& c, void* data, std::size_t n, MPI_Datatype type) {
    MPI_Request r;
    MPI_Ibcast(data, count_of(n), type, 0, MPI_COMM_WORLD, &r);
    c.wait(&r, "an MPI broadcast");
  }
};

void Communicator::sum(std::span<float> v) const {
  if (distributed()) Collective::allreduce(*this, v.data(), v.size(), MPI_FLOAT, MPI_SUM);
}

void Communicator::sum(std::span<double> v) const {
  if (distributed()) Collective::allreduce(*this, v.data(), v.size(), MPI_DOUBLE, MPI_SUM);
}

void Communicator::sum(std::span<std::int64_t> v) const {
  if (distributed()) Collective::allreduce(*this, v.data(), v.size(), MPI_INT64_T, MPI_SUM);
}

void Communicator::bitwise_or(std::span<std::uint32_t> v) const {
  if (distributed()) Collective::allreduce(*this, v.data(), v.size(), MPI_UINT32_T, MPI_BOR);
}

double Communicator::max(double value) const {
  if (distributed()) Collective::allreduce(*this, &value, 1, MPI_DOUBLE, MPI_MAX);
  return value;
}

void Communicator::broadcast(std::string& bytes) const {
  if (!distributed()) return;
  std::uint64_t n = bytes.size();
  Collective::broadcast(*this, &n, 1, MPI_UINT64_T);
  bytes.resize(n);
  Collective::broadcast(*this, bytes.data(), n, MPI_CHAR);
}

void Communicator::broadcast(std::span<std::uint64_t> v) const {
  if (distributed()) Collective::broadcast(*this, v.data(), v.size(), MPI_UINT64_T);
}

void Communicator::broadcast(std::span<float> v) const {
  if (distributed()) Collective::broadcast(*this, v.data(), v.size(), MPI_FLOAT);
}

void Communicator::require_same(const std::string& what, std::uint64_t digest) const {
  if (!distributed()) return;
  std::vector<std::uint64_t> all(static_cast<std::size_t>(size_));
  MPI_Request r;
  MPI_Iallgather(&digest, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD, &r);
  wait(&r, "comparing the ranks' work");
  for (int k = 1; k < size_; ++k)
    if (all[std::size_t(k)] != all[0])
      throw JobInputError("rank " + std::to_string(k) + " was given other work than rank 0: " + what +
                          " differ (every rank must get the same; only --device may differ)");
}

std::vector<float> Communicator::gather(std::span<const float> part) const {
  if (!distributed()) return {part.begin(), part.end()};
  const int mine = count_of(part.size());
  std::vector<int> counts(rank_ == 0 ? std::size_t(size_) : 0), offsets;
  MPI_Request r;
  MPI_Igather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD, &r);
  wait(&r, "an MPI gather");
  std::vector<float> all;
  if (rank_ == 0) {
    std::size_t total = 0;
    for (const int c : counts) {
      offsets.push_back(count_of(total));
      total += std::size_t(c);
    }
    all.resize(total);
  }
  MPI_Igatherv(part.data(), mine, MPI_FLOAT, all.data(), counts.data(), offsets.data(), MPI_FLOAT, 0, MPI_COMM_WORLD,
               &r);
  wait(&r, "an MPI gather");
  return all;
}

int Communicator::finish(int code, bool together) {
  if (!mpi_) return code;
  // Peers of a failed rank may be blocked in a collective that will never complete: only an abort ends them.
  if (code != 0 && distributed() && !together) MPI_Abort(MPI_COMM_WORLD, code);
  MPI_Finalize();
  mpi_ = false;
  return code;
}

}  // namespace clr::distributed
