#pragma once
// Platform/device enumeration and the --device SPEC rule (docs/design.md §4):
//   "P:D"      platform and device indices, as `clradiosity devices` prints them;
//   otherwise  a case-insensitive substring of the platform name or vendor, the device name or its type
//              ("pocl" matches PoCL's vendor "The pocl project"; "nvidia", "cpu", "gpu").
// No spec (and no CLRADIOSITY_DEVICE): the first GPU, else the first CPU, else the first device.
#include <CL/cl.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clr::cl {

struct DeviceInfo {
  unsigned platform_index = 0;
  unsigned device_index = 0;
  cl_platform_id platform = nullptr;
  cl_device_id device = nullptr;
  std::string platform_name;
  std::string platform_vendor;
  std::string name;
  std::string type;  // "cpu", "gpu", "accelerator" or "other"
  unsigned compute_units = 0;
  std::uint64_t global_mem_bytes = 0;
  std::uint64_t max_alloc_bytes = 0;
  std::size_t max_work_group_size = 0;
  std::string opencl_c_version;
  bool float_atomics = false;  // cl_ext_float_atomics; otherwise kernels use CAS loops (docs/design.md §5)
  bool fp16 = false;           // cl_khr_fp16

  std::string spec() const { return std::to_string(platform_index) + ":" + std::to_string(device_index); }
  // One line for listings and error messages: "0:0  Portable Computing Language / pthread-... (cpu)".
  std::string describe() const;
};

// Every device of every platform. An absent ICD (no platforms) yields an empty list, not an error.
std::vector<DeviceInfo> list_devices();

// Resolves SPEC (empty: CLRADIOSITY_DEVICE, then the default rule) against `devices`: the first match, or with
// `nth` the nth of the matches round-robin (an MPI rank passes its local rank; "P:D" pins one device).
// Throws InputError naming the spec and listing what exists when nothing matches.
DeviceInfo select_device(const std::vector<DeviceInfo>& devices, const std::string& spec, unsigned nth = 0);
DeviceInfo select_device(const std::string& spec = "", unsigned nth = 0);

}  // namespace clr::cl
