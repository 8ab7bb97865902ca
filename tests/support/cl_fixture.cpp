#include "support/cl_fixture.hpp"

#include <memory>

#include "cl/device.hpp"

namespace clr::test {

cl::Context* shared_context() {
  // Tests run on the device CLRADIOSITY_DEVICE names, else the default rule (PoCL in CI).
  static std::unique_ptr<cl::Context> ctx = []() -> std::unique_ptr<cl::Context> {
    const auto devices = cl::list_devices();
    if (devices.empty()) return nullptr;
    return std::make_unique<cl::Context>(cl::select_device(devices, ""));
  }();
  return ctx.get();
}

}  // namespace clr::test
