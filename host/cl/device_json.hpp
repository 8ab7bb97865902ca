#pragma once
// A device as `clradiosity devices --json` lists it, and the Python module's devices() returns it.
#include <nlohmann/json.hpp>

#include "cl/device.hpp"

namespace clr::cl {

nlohmann::json to_json(const DeviceInfo& device, bool is_default);

}  // namespace clr::cl
