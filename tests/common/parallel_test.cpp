#include "common/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/error.hpp"

namespace clr {
namespace {

// Restores the default pool size when a test ends, whatever it set.
struct ThreadCountGuard {
  ~ThreadCountGuard() { set_thread_count(0); }
};

TEST(ParallelFor, VisitsEveryIndexOnceInChunksOfAtMostTheGrain) {
  for (const std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(7), std::size_t(1000), std::size_t(4097)})
    for (const std::size_t chunk : {std::size_t(0), std::size_t(1), std::size_t(64), std::size_t(5000)}) {
      std::vector<std::atomic<int>> seen(n);
      std::atomic<bool> chunk_too_large{false};
      parallel_for(n, chunk, [&](std::size_t b, std::size_t e) {
        if (e - b > std::max<std::size_t>(chunk, 1)) chunk_too_large = true;
        for (std::size_t i = b; i < e; ++i) ++seen[i];
      });
      EXPECT_FALSE(chunk_too_large) << n << " " << chunk;
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(seen[i], 1) << "index " << i << " of " << n;
    }
}

TEST(ParallelFor, RethrowsTheBodysExceptionAndStops) {
  std::atomic<std::size_t> ran{0};
  EXPECT_THROW(parallel_for(100000, 1,
                            [&](std::size_t b, std::size_t) {
                              ++ran;
                              // Every chunk from 10 on fails: whichever worker meets one first, however the
                              // threads are scheduled (one failing chunk could be the last one run, on a loaded
                              // machine).
                              if (b >= 10) throw std::runtime_error("chunk " + std::to_string(b));
                            }),
               std::runtime_error);
  // Cancelled: far from every chunk ran after the failure (a loop that ignored it would run all 100000).
  EXPECT_LT(ran.load(), 100000u);
}

TEST(ParallelFor, NestsWithoutDeadlock) {
  std::atomic<std::size_t> total{0};
  parallel_for(16, 1, [&](std::size_t, std::size_t) {
    parallel_for(64, 4, [&](std::size_t b, std::size_t e) { total += e - b; });
  });
  EXPECT_EQ(total, 16u * 64u);
}

TEST(ParallelFor, ThreadCountCapsTheWorkers) {
  ThreadCountGuard guard;
  const std::size_t all = worker_count();
  set_thread_count(1);
  EXPECT_EQ(worker_count(), 1u);
  std::mutex m;
  std::set<std::thread::id> threads;
  parallel_for(256, 1, [&](std::size_t, std::size_t) {
    std::lock_guard lock(m);
    threads.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(threads.size(), 1u);
  set_thread_count(0);
  EXPECT_EQ(worker_count(), all);
  EXPECT_THROW(set_thread_count(1u << 20), InputError);
}

}  // namespace
}  // namespace clr
