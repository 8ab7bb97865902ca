#pragma once
// Tests that need an OpenCL device derive from ClTest: it skips (never fails) when no device exists, and
// otherwise hands out one Context per test binary, so compiled programs are reused across tests.
#include <gtest/gtest.h>

#include <string>

#include "cl/context.hpp"

namespace clr::test {

// The shared context, or nullptr when this machine has no OpenCL device.
cl::Context* shared_context();

// A test lane names the implementation it runs on (CLR_TEST_EXPECT_DEVICE, a substring of the device's
// description); this says how `ctx` differs from it, or "" when it matches or nothing is expected. A lane whose
// runtime failed to load must fail, not skip every test and pass.
std::string unexpected_device(const cl::Context* ctx);

class ClTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ctx_ = shared_context();
    if (const auto why = unexpected_device(ctx_); !why.empty()) FAIL() << why;
    if (!ctx_) GTEST_SKIP() << "no OpenCL device (install pocl-opencl-icd)";
  }
  cl::Context& ctx() { return *ctx_; }

 private:
  cl::Context* ctx_ = nullptr;
};

}  // namespace clr::test
