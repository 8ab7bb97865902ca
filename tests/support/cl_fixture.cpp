#include "support/cl_fixture.hpp"

#include <clblast.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "cl/device.hpp"

namespace clr::test {
namespace {

std::unique_ptr<cl::Context>& context_slot() {
  static std::unique_ptr<cl::Context> ctx;
  return ctx;
}

// OpenCL objects must be released while the runtime is still alive, not by static destructors at exit: Oclgrind
// frees its thread-local state first and then aborts on the late release ("corrupted double-linked list"). The
// environment's TearDown runs when RUN_ALL_TESTS ends, before main returns; CLBlast's program cache goes with it.
class ReleaseSharedContext : public ::testing::Environment {
 public:
  void TearDown() override {
    if (!context_slot()) return;
    clblast::ClearCache();
    context_slot().reset();
  }
};
[[maybe_unused]] ::testing::Environment* const release_at_end =
    ::testing::AddGlobalTestEnvironment(new ReleaseSharedContext);

}  // namespace

std::string unexpected_device(const cl::Context* ctx) {
  const char* want = std::getenv("CLR_TEST_EXPECT_DEVICE");
  if (!want || !*want) return "";
  if (!ctx) return std::string("no OpenCL device, but this run expects '") + want + "' (CLR_TEST_EXPECT_DEVICE)";
  const auto got = ctx->device().describe();
  if (got.find(want) == std::string::npos)
    return "running on " + got + ", but this run expects '" + want + "' (CLR_TEST_EXPECT_DEVICE)";
  return "";
}

cl::Context* shared_context() {
  // Tests run on the device CLRADIOSITY_DEVICE names, else the default rule (PoCL in CI).
  static const bool created = [] {
    const auto devices = cl::list_devices();
    if (!devices.empty()) {
      context_slot() = std::make_unique<cl::Context>(cl::select_device(devices, ""));
      // Which implementation ran the tests, for the log of every lane (tests/runtimes/lanes.cmake).
      std::printf("[  device  ] %s\n", context_slot()->device().describe().c_str());
    }
    return true;
  }();
  (void)created;
  return context_slot().get();
}

}  // namespace clr::test
