// Real kernels from kernels/ against double-precision host twins, with canaries after the outputs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "cl/buffer.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

class ReduceKernel : public ClTest {
 protected:
  // Returns the device sum and the count of skipped non-finite values.
  std::pair<float, unsigned> device_sum(const std::vector<float>& x) {
    cl::Buffer<float> in(ctx(), std::span<const float>(x));
    auto total_host = with_canaries(1);
    cl::Buffer<float> total(ctx(), std::span<const float>(total_host));
    cl::Buffer<unsigned> bad(ctx(), 1);
    bad.fill(0u);
    const std::size_t local = 64;
    ctx()
        .program({"atomics.cl", "reduce.cl"})
        .kernel("sum_f32")
        .args(in, unsigned(x.size()), total, bad, cl::LocalMemory{local * sizeof(float)})
        .launch(x.size(), local);
    total.read(total_host);
    EXPECT_TRUE(canaries_intact(total_host, 1));
    return {total_host[0], bad.read()[0]};
  }
};

TEST_F(ReduceKernel, SumMatchesDoubleTwin) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 2.0f);
  for (std::size_t n : {1u, 63u, 64u, 65u, 1000u, 100003u}) {
    std::vector<float> x(n);
    for (auto& v : x) v = u(rng);
    const double twin = std::accumulate(x.begin(), x.end(), 0.0);
    const auto [got, bad] = device_sum(x);
    EXPECT_TRUE(near(got, twin)) << "n=" << n;
    EXPECT_EQ(bad, 0u);
  }
}

TEST_F(ReduceKernel, NonFiniteValuesAreDroppedAndCounted) {
  std::vector<float> x(1000, 0.5f);
  x[3] = std::numeric_limits<float>::quiet_NaN();
  x[500] = std::numeric_limits<float>::infinity();
  x[999] = -std::numeric_limits<float>::infinity();
  const auto [got, bad] = device_sum(x);
  EXPECT_TRUE(near(got, 997 * 0.5));
  EXPECT_EQ(bad, 3u);
}

TEST_F(ClTest, FillWritesExactlyTheRange) {
  const std::size_t n = 1001;  // not a multiple of the work-group size: the launch pads, the kernel bounds-checks
  auto host = with_canaries(n);
  cl::Buffer<float> buf(ctx(), std::span<const float>(host));
  ctx().program({"atomics.cl", "reduce.cl"}).kernel("fill_f32").args(buf, unsigned(n), 3.25f).launch(n);
  buf.read(host);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(host[i], 3.25f) << i;
  EXPECT_TRUE(canaries_intact(host, n));
}

}  // namespace
}  // namespace clr::test
