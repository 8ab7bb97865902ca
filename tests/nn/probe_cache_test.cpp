// The probe cache's key: one entry per device as the host sees it, so a context that reports the same device as a
// GPU (the tests' GPU-shaped PoCL) neither reads nor overwrites the times measured with the CPU's launch shapes.
#include "nn/probe_cache.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

class ProbeCacheTest : public ClTest {
 protected:
  void SetUp() override {
    ClTest::SetUp();
    if (const char* old = std::getenv("XDG_CACHE_HOME")) saved_ = old;
    dir_ = fs::temp_directory_path() / ("clr_probe_cache_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    ::setenv("XDG_CACHE_HOME", dir_.c_str(), 1);
  }
  void TearDown() override {
    if (saved_)
      ::setenv("XDG_CACHE_HOME", saved_->c_str(), 1);
    else
      ::unsetenv("XDG_CACHE_HOME");
    fs::remove_all(dir_);
  }

 private:
  fs::path dir_;
  std::optional<std::string> saved_;
};

TEST_F(ProbeCacheTest, KeysTheTypeTheDeviceReports) {
  cl::DeviceInfo gpu = ctx().device();
  gpu.type = cl::DeviceType::Gpu;
  cl::Context gpu_shaped(gpu);
  {
    nn::ProbeCache cpu(ctx());
    EXPECT_EQ(cpu.seconds("candidate", [] { return 1.0; }), 1.0);
  }
  {
    nn::ProbeCache other(gpu_shaped);
    EXPECT_EQ(other.seconds("candidate", [] { return 2.0; }), 2.0) << "read the CPU-typed context's time";
  }
  nn::ProbeCache cpu(ctx());
  EXPECT_EQ(cpu.seconds("candidate", [] { return 3.0; }), 1.0) << "the CPU-typed context's time was not kept";
}

}  // namespace
}  // namespace clr::test
