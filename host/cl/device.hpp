#pragma once
// Platform/device enumeration and the --device SPEC rule (docs/design.md §4):
//   "P:D"      platform and device indices, as `clradiosity devices` prints them;
//   otherwise  a case-insensitive substring of the platform name or vendor, the device name or its type
//              ("pocl" matches PoCL's vendor "The pocl project"; "nvidia", "cpu", "gpu").
// No spec (and no CLRADIOSITY_DEVICE): the first GPU, else the first CPU, else the first device — never a
// simulator (Oclgrind reports itself as a GPU but interprets every work-item; it is for checking kernels, and only
// a spec that names it selects it).
// CLRADIOSITY_EMULATE_LIMITS=nvidia clamps what every device reports to an NVIDIA GPU's OpenCL limits (work-group
// 1024, local memory 48 KiB, max allocation ¼ of global memory, no fp16, no float atomics, no sub-groups), so the
// host's choices and launch checks can be exercised on a CPU device (docs/nvidia.md).
#include <CL/cl.h>

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace clr::cl {

enum class DeviceType { Cpu, Gpu, Accelerator, Other };
// "cpu", "gpu", "accelerator", "other": as listings print it and --device SPEC matches it.
const char* type_name(DeviceType type);

struct DeviceInfo {
  unsigned platform_index = 0;
  unsigned device_index = 0;
  cl_platform_id platform = nullptr;
  cl_device_id device = nullptr;
  std::string platform_name;
  std::string platform_vendor;
  std::string name;
  DeviceType type = DeviceType::Other;
  unsigned compute_units = 0;
  std::uint64_t global_mem_bytes = 0;
  std::uint64_t max_alloc_bytes = 0;
  std::size_t max_work_group_size = 0;
  std::uint64_t local_mem_bytes = 0;
  std::string opencl_c_version;
  std::string driver_version;  // CL_DRIVER_VERSION (NVIDIA: the driver's release, e.g. 580.159.04)
  bool float_atomics = false;  // cl_ext_float_atomics; otherwise kernels use CAS loops (docs/design.md §5)
  bool fp16 = false;           // cl_khr_fp16
  bool int64_atomics = false;  // cl_khr_int64_base_atomics: hash-grid gradients in fixed point (docs/design.md §5)
  bool sub_groups = false;     // cl_khr_subgroups or cl_intel_subgroups (no kernel relies on them)
  unsigned nv_compute_capability = 0;  // cl_nv_device_attribute_query: major·10 + minor (H100/H200: 90); 0 elsewhere
  bool simulator = false;              // Oclgrind: never the default device
  std::string emulated;                // "nvidia" when CLRADIOSITY_EMULATE_LIMITS clamped the figures above

  std::string spec() const { return std::to_string(platform_index) + ":" + std::to_string(device_index); }
  // One line for listings and error messages: "0:0  Portable Computing Language / pthread-... (cpu)".
  std::string describe() const;
};

// Every device of every platform, clamped by CLRADIOSITY_EMULATE_LIMITS when it is set (an unknown value throws
// InputError). An absent ICD (no platforms) yields an empty list, not an error.
std::vector<DeviceInfo> list_devices();
// Held while the platforms are discovered (list_devices) and while a context is made: the ICD loader's and a
// runtime's first-use initialisation are not safe to enter from two threads at once (two Python threads whose first
// call is `train`: a crash, or a false "no OpenCL platform"). Recursive: a context made inside a listing is fine.
std::recursive_mutex& opencl_startup_mutex();

// Clamps `device` to NVIDIA's OpenCL limits (what CLRADIOSITY_EMULATE_LIMITS=nvidia applies).
void emulate_nvidia_limits(DeviceInfo& device);
// CLRADIOSITY_EMULATE_LIMITS: true for "nvidia", false when unset or empty; InputError naming it otherwise.
bool emulating_nvidia_limits();

// Resolves SPEC (empty: CLRADIOSITY_DEVICE, then the default rule) against `devices`: the first match, or with
// `nth` the nth of the matches round-robin (an MPI rank passes its local rank; "P:D" pins one device).
// Throws InputError naming the spec and listing what exists when nothing matches.
DeviceInfo select_device(const std::vector<DeviceInfo>& devices, const std::string& spec, unsigned nth = 0);
DeviceInfo select_device(const std::string& spec = "", unsigned nth = 0);

}  // namespace clr::cl
