#include "cl/device.hpp"

#include <CL/cl_ext.h>  // CL_DEVICE_COMPUTE_CAPABILITY_*_NV

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>

#include "cl/error.hpp"
#include "cl/no_platform.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"

namespace clr::cl {
namespace {

std::string platform_string(cl_platform_id p, cl_platform_info what) {
  std::size_t n = 0;
  CLR_CL_CHECK(clGetPlatformInfo(p, what, 0, nullptr, &n));
  std::string s(n, '\0');
  CLR_CL_CHECK(clGetPlatformInfo(p, what, n, s.data(), nullptr));
  return s.c_str();  // drop the terminating NUL the size includes
}

std::string device_string(cl_device_id d, cl_device_info what) {
  std::size_t n = 0;
  CLR_CL_CHECK(clGetDeviceInfo(d, what, 0, nullptr, &n));
  std::string s(n, '\0');
  CLR_CL_CHECK(clGetDeviceInfo(d, what, n, s.data(), nullptr));
  return s.c_str();
}

template <typename T>
T device_value(cl_device_id d, cl_device_info what) {
  T v{};
  CLR_CL_CHECK(clGetDeviceInfo(d, what, sizeof(T), &v, nullptr));
  return v;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

DeviceType device_type(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return DeviceType::Gpu;
  if (t & CL_DEVICE_TYPE_CPU) return DeviceType::Cpu;
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return DeviceType::Accelerator;
  return DeviceType::Other;
}

bool has_extension(const std::string& extensions, const std::string& ext) {
  return (" " + extensions + " ").find(" " + ext + " ") != std::string::npos;
}

std::optional<std::pair<unsigned, unsigned>> parse_indices(const std::string& spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos) return std::nullopt;
  unsigned p = 0, d = 0;
  const char* b = spec.data();
  const char* e = b + spec.size();
  auto r1 = std::from_chars(b, b + colon, p);
  auto r2 = std::from_chars(b + colon + 1, e, d);
  if (r1.ec != std::errc() || r1.ptr != b + colon || r2.ec != std::errc() || r2.ptr != e) return std::nullopt;
  return std::pair{p, d};
}

}  // namespace

const char* type_name(DeviceType type) {
  switch (type) {
    case DeviceType::Cpu:
      return "cpu";
    case DeviceType::Gpu:
      return "gpu";
    case DeviceType::Accelerator:
      return "accelerator";
    case DeviceType::Other:
      break;
  }
  return "other";
}

std::string DeviceInfo::describe() const {
  return spec() + "  " + platform_name + " / " + name + " (" + type_name(type) + ")" +
         (emulated.empty() ? "" : " [" + emulated + " limits]");
}

void emulate_nvidia_limits(DeviceInfo& d) {
  // NVIDIA's OpenCL on every GPU since Volta: 1024 work-items a group, 48 KiB of __local memory a group, a largest
  // allocation of a quarter of device memory; it has cl_khr_int64_base_atomics (kept as the device reports it) but
  // neither cl_khr_fp16, cl_ext_float_atomics nor sub-groups.
  d.max_work_group_size = std::min<std::size_t>(d.max_work_group_size, 1024);
  d.local_mem_bytes = std::min<std::uint64_t>(d.local_mem_bytes, 48 * 1024);
  d.max_alloc_bytes = std::min<std::uint64_t>(d.max_alloc_bytes, d.global_mem_bytes / 4);
  d.fp16 = false;
  d.float_atomics = false;
  d.sub_groups = false;
  d.emulated = "nvidia";
}

bool emulating_nvidia_limits() {
  const char* env = std::getenv("CLRADIOSITY_EMULATE_LIMITS");
  if (!env || !*env) return false;
  if (lower(env) != "nvidia") throw InputError("CLRADIOSITY_EMULATE_LIMITS='" + clip(env) + "' is not one of: nvidia");
  return true;
}

std::recursive_mutex& opencl_startup_mutex() {
  static std::recursive_mutex m;
  return m;
}

std::vector<DeviceInfo> list_devices() {
  const bool emulate_nvidia = emulating_nvidia_limits();
  const std::lock_guard<std::recursive_mutex> lock(opencl_startup_mutex());
  cl_uint np = 0;
  const cl_int status = clGetPlatformIDs(0, nullptr, &np);
  if (status == -1001 /* CL_PLATFORM_NOT_FOUND_KHR: the ICD loader found no driver */ || np == 0) return {};
  CLR_CL_CHECK(status);
  std::vector<cl_platform_id> platforms(np);
  CLR_CL_CHECK(clGetPlatformIDs(np, platforms.data(), nullptr));

  std::vector<DeviceInfo> out;
  for (unsigned pi = 0; pi < np; ++pi) {
    cl_uint nd = 0;
    if (clGetDeviceIDs(platforms[pi], CL_DEVICE_TYPE_ALL, 0, nullptr, &nd) != CL_SUCCESS || nd == 0) continue;
    std::vector<cl_device_id> devices(nd);
    CLR_CL_CHECK(clGetDeviceIDs(platforms[pi], CL_DEVICE_TYPE_ALL, nd, devices.data(), nullptr));
    for (unsigned di = 0; di < nd; ++di) {
      const cl_device_id d = devices[di];
      DeviceInfo info;
      info.platform_index = pi;
      info.device_index = di;
      info.platform = platforms[pi];
      info.device = d;
      info.platform_name = platform_string(platforms[pi], CL_PLATFORM_NAME);
      info.platform_vendor = platform_string(platforms[pi], CL_PLATFORM_VENDOR);
      info.name = device_string(d, CL_DEVICE_NAME);
      info.type = device_type(device_value<cl_device_type>(d, CL_DEVICE_TYPE));
      info.compute_units = device_value<cl_uint>(d, CL_DEVICE_MAX_COMPUTE_UNITS);
      info.global_mem_bytes = device_value<cl_ulong>(d, CL_DEVICE_GLOBAL_MEM_SIZE);
      info.max_alloc_bytes = device_value<cl_ulong>(d, CL_DEVICE_MAX_MEM_ALLOC_SIZE);
      info.max_work_group_size = device_value<std::size_t>(d, CL_DEVICE_MAX_WORK_GROUP_SIZE);
      info.local_mem_bytes = device_value<cl_ulong>(d, CL_DEVICE_LOCAL_MEM_SIZE);
      info.opencl_c_version = device_string(d, CL_DEVICE_OPENCL_C_VERSION);
      info.driver_version = device_string(d, CL_DRIVER_VERSION);
      const std::string ext = device_string(d, CL_DEVICE_EXTENSIONS);
      info.float_atomics = has_extension(ext, "cl_ext_float_atomics");
      info.fp16 = has_extension(ext, "cl_khr_fp16");
      info.int64_atomics = has_extension(ext, "cl_khr_int64_base_atomics");
      info.sub_groups = has_extension(ext, "cl_khr_subgroups") || has_extension(ext, "cl_intel_subgroups");
      if (has_extension(ext, "cl_nv_device_attribute_query"))
        info.nv_compute_capability = 10 * device_value<cl_uint>(d, CL_DEVICE_COMPUTE_CAPABILITY_MAJOR_NV) +
                                     device_value<cl_uint>(d, CL_DEVICE_COMPUTE_CAPABILITY_MINOR_NV);
      info.simulator = lower(info.platform_name).find("oclgrind") != std::string::npos;
      if (emulate_nvidia) emulate_nvidia_limits(info);
      out.push_back(std::move(info));
    }
  }
  return out;
}

DeviceInfo select_device(const std::vector<DeviceInfo>& devices, const std::string& requested, unsigned nth) {
  std::string spec = requested;
  std::string origin = "--device";
  if (spec.empty()) {
    if (const char* env = std::getenv("CLRADIOSITY_DEVICE"); env && *env) {
      spec = env;
      origin = "CLRADIOSITY_DEVICE";
    }
  }

  auto fail = [&](const std::string& why) -> DeviceInfo {
    std::string msg = why + "; available:";
    for (const auto& d : devices) msg += "  [" + d.describe() + "]";
    throw InputError(msg);
  };
  // No device at all is the machine's state, whatever was asked for (exit 1, naming the cause).
  if (devices.empty()) throw std::runtime_error(no_platform_cause());

  // The matches in listing order; the nth of them, round-robin, so ranks on one machine spread over its devices.
  std::vector<const DeviceInfo*> matches;
  const auto pick = [&] { return *matches[nth % matches.size()]; };
  if (spec.empty()) {
    for (const DeviceType type : {DeviceType::Gpu, DeviceType::Cpu}) {
      for (const auto& d : devices)
        if (d.type == type && !d.simulator) matches.push_back(&d);
      if (!matches.empty()) return pick();
    }
    for (const auto& d : devices)
      if (!d.simulator) matches.push_back(&d);
    if (!matches.empty()) return pick();
    return fail("no OpenCL device but a simulator (name it, e.g. --device oclgrind, to run on it)");
  }
  if (const auto idx = parse_indices(spec)) {
    for (const auto& d : devices)
      if (d.platform_index == idx->first && d.device_index == idx->second) return d;
    return fail(origin + " '" + spec + "' names no device");
  }
  const std::string needle = lower(spec);
  for (const auto& d : devices)
    if (lower(d.platform_name + " " + d.platform_vendor + " " + d.name + " " + type_name(d.type)).find(needle) !=
        std::string::npos)
      matches.push_back(&d);
  if (!matches.empty()) return pick();
  return fail(origin + " '" + spec + "' matches no device");
}

DeviceInfo select_device(const std::string& spec, unsigned nth) { return select_device(list_devices(), spec, nth); }

}  // namespace clr::cl
