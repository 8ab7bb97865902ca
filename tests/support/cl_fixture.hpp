#pragma once
// Tests that need an OpenCL device derive from ClTest: it skips (never fails) when no device exists, and
// otherwise hands out one Context per test binary, so compiled programs are reused across tests.
#include <gtest/gtest.h>

#include "cl/context.hpp"

namespace clr::test {

// The shared context, or nullptr when this machine has no OpenCL device.
cl::Context* shared_context();

class ClTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ctx_ = shared_context();
    if (!ctx_) GTEST_SKIP() << "no OpenCL device (install pocl-opencl-icd)";
  }
  cl::Context& ctx() { return *ctx_; }

 private:
  cl::Context* ctx_ = nullptr;
};

}  // namespace clr::test
