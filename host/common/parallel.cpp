#include "common/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <string>

#include "common/error.hpp"

namespace clr {
namespace {

// The process's cap, alive until exit (oneTBB applies the most restrictive live global_control).
std::unique_ptr<tbb::global_control>& thread_limit() {
  static std::unique_ptr<tbb::global_control> limit;
  return limit;
}

}  // namespace

void set_thread_count(std::size_t threads) {
  constexpr std::size_t kMaxThreads = 4096;
  if (threads > kMaxThreads)
    throw InputError("--threads " + std::to_string(threads) + " is more than " + std::to_string(kMaxThreads));
  thread_limit().reset();
  if (threads == 0) return;
  thread_limit() = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  // PoCL's CPU device reads its thread count once, when the OpenCL platform starts (POCL_MAX_PTHREAD_COUNT in
  // Debian 12's PoCL 3.1, POCL_CPU_MAX_CU_NUM from 4.0 on); a value the user set wins.
  for (const char* name : {"POCL_MAX_PTHREAD_COUNT", "POCL_CPU_MAX_CU_NUM"})
    ::setenv(name, std::to_string(threads).c_str(), 0);
}

std::size_t worker_count() { return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism); }

void parallel_for(std::size_t n, std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& body) {
  if (n == 0) return;
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t chunks = (n + chunk - 1) / chunk;
  // One task a chunk (simple_partitioner with grain 1): the chunk sizes callers pick are already their grain. An
  // exception cancels the remaining chunks and is rethrown here by oneTBB.
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, chunks, 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t c = range.begin(); c != range.end(); ++c) body(c * chunk, std::min(n, (c + 1) * chunk));
      },
      tbb::simple_partitioner());
}

}  // namespace clr
