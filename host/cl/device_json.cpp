#include "cl/device_json.hpp"

namespace clr::cl {

nlohmann::json to_json(const cl::DeviceInfo& d, bool is_default) {
  return {{"index", d.spec()},
          {"platform", d.platform_name},
          {"name", d.name},
          {"type", cl::type_name(d.type)},
          {"compute_units", d.compute_units},
          {"global_mem_bytes", d.global_mem_bytes},
          {"max_alloc_bytes", d.max_alloc_bytes},
          {"opencl_c_version", d.opencl_c_version},
          {"driver", d.driver_version},
          {"float_atomics", d.float_atomics},
          {"fp16", d.fp16},
          {"nv_compute_capability",
           d.nv_compute_capability ? nlohmann::json(d.nv_compute_capability / 10.0) : nlohmann::json()},
          {"default", is_default}};
}

}  // namespace clr::cl
