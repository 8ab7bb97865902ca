// The device's busy time (cl::Context::record_device_time): what benchmarks print beside a step's host stages.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "cl/async.hpp"
#include "cl/buffer.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

class DeviceTime : public ClTest {
 protected:
  void sum(cl::Buffer<float>& in, cl::Buffer<float>& total, cl::Buffer<unsigned>& bad, std::size_t n) {
    ctx()
        .program({"atomics.cl", "reduce.cl"})
        .kernel("sum_f32")
        .args(in, unsigned(n), total, bad, cl::LocalMemory{64 * sizeof(float)})
        .launch(n, 64);
  }
};

TEST_F(DeviceTime, CountsRecordedCommandsButNotTheHostsIdleGaps) {
  const std::size_t n = 1 << 20;
  const std::vector<float> ones(n, 1.0f);
  cl::Buffer<float> in(ctx(), std::span<const float>(ones)), total(ctx(), 1);
  cl::Buffer<unsigned> bad(ctx(), 1);
  sum(in, total, bad, n);  // builds the program outside the measurement
  ctx().finish();

  EXPECT_EQ(ctx().take_device_seconds(), 0.0);  // nothing recorded while off
  ctx().record_device_time(true);
  total.fill(0.0f);
  sum(in, total, bad, n);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the host idles: the device has nothing to do
  sum(in, total, bad, n);
  std::vector<float> result(1);
  total.read(result);
  const auto start = std::chrono::steady_clock::now();
  const double busy = ctx().take_device_seconds();
  ctx().record_device_time(false);
  const double wall_after = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(result[0], 2.0f * float(n));
  EXPECT_GT(busy, 0.0);
  EXPECT_LT(busy, 0.3);  // the sleep is not device time
  EXPECT_LT(wall_after, 1.0);
  // Taken: the next call starts from nothing.
  EXPECT_EQ(ctx().take_device_seconds(), 0.0);
}

TEST_F(DeviceTime, CountsPinnedUploads) {
  cl::Buffer<float> dst(ctx(), 1);
  cl::PinnedUpload<float> up;
  ctx().record_device_time(true);
  up.send(ctx(), dst, std::vector<float>(1 << 20, 3.0f));
  const double busy = ctx().take_device_seconds();
  ctx().record_device_time(false);
  EXPECT_GT(busy, 0.0);
  EXPECT_EQ(dst.read()[5], 3.0f);
}

}  // namespace
}  // namespace clr::test
