// cl::PinnedDownload reads on the context's transfer queue: it must still see everything the main queue enqueued
// before it, and hand back those values even when the source is overwritten after wait().
#include <gtest/gtest.h>

#include <vector>

#include "cl/async.hpp"
#include "cl/buffer.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

TEST_F(ClTest, PinnedDownloadSeesTheMainQueuesEarlierWritesAndKeepsThem) {
  const std::size_t n = 1 << 20;
  cl::Buffer<float> src(ctx(), n);
  cl::PinnedDownload<float> down;
  for (int round = 1; round <= 3; ++round) {
    // Not waited for: the download must follow the fill by the marker alone.
    src.fill(float(round));
    down.start(ctx(), src, n);
    down.wait();
    src.fill(-1.0f);  // overwritten after the read, as the guided directions' next draw does
    const auto got = down.result();
    ASSERT_EQ(got.size(), n);
    EXPECT_EQ(got.front(), float(round));
    EXPECT_EQ(got[n / 2], float(round));
    EXPECT_EQ(got.back(), float(round));
  }
  // A download of nothing, and one of a prefix.
  down.start(ctx(), src, 0);
  EXPECT_TRUE(down.result().empty());
  src.fill(7.0f);
  down.start(ctx(), src, 5);
  EXPECT_EQ(std::vector<float>(down.result().begin(), down.result().end()), std::vector<float>(5, 7.0f));
  ctx().finish();
}

}  // namespace
}  // namespace clr::test
