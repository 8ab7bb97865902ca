// clradiosity devices [--json] [--device SPEC]
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cl/device.hpp"
#include "cl/device_json.hpp"
#include "cli/command.hpp"

namespace clr::cli {
namespace {

std::string gib(std::uint64_t bytes) {
  char s[32];
  std::snprintf(s, sizeof s, "%.2f GiB", double(bytes) / double(1ull << 30));
  return s;
}

}  // namespace

Command add_devices_command(CLI::App& app) {
  struct Options {
    bool json = false;
    std::string device;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("devices", "List OpenCL platforms and devices (the default is marked *)");
  cmd->add_flag("--json", opt->json, "Print one JSON array");
  add_device_option(*cmd, opt->device);

  return {cmd, [opt]() {
            auto devices = cl::list_devices();
            // The default (or the one --device names) is resolved through the same rule every command uses, so a bad
            // spec fails here exactly as it would elsewhere: exit 2 with the list of what exists.
            const auto chosen = cl::select_device(devices, opt->device);
            if (!opt->device.empty()) devices = {chosen};

            if (opt->json) {
              auto out = nlohmann::json::array();
              for (const auto& d : devices) out.push_back(cl::to_json(d, d.device == chosen.device));
              std::cout << out.dump(2) << "\n";
              return 0;
            }
            for (const auto& d : devices) {
              std::cout << (d.device == chosen.device ? "* " : "  ") << d.describe() << "\n"
                        << "      compute units " << d.compute_units << ", global memory " << gib(d.global_mem_bytes)
                        << ", max buffer " << gib(d.max_alloc_bytes) << ", " << d.opencl_c_version << ", float atomics "
                        << (d.float_atomics ? "yes" : "no (CAS loops)") << ", fp16 " << (d.fp16 ? "yes" : "no");
              // NVIDIA: the compute capability decides whether the TF32 tensor-core GEMM is a candidate (8.0+).
              if (d.nv_compute_capability)
                std::cout << ", compute capability " << d.nv_compute_capability / 10 << "."
                          << d.nv_compute_capability % 10;
              std::cout << "\n";
            }
            return 0;
          }};
}

}  // namespace clr::cli
