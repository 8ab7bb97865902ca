#pragma once
// OpenCL C sources by file name ("util.cl"). Normally the copies embedded at build time; with
// CLRADIOSITY_KERNEL_DIR set, read from that folder instead so kernels can be edited without a rebuild.
#include <string>
#include <vector>

namespace clr::cl {

std::string kernel_source(const std::string& file);
std::vector<std::string> embedded_kernel_files();

// InputError naming the variable unless CLRADIOSITY_KERNEL_DIR (a folder) and CLRADIOSITY_KERNEL_WARNINGS ("error")
// are unset, empty or usable.
void check_kernel_environment();

}  // namespace clr::cl
