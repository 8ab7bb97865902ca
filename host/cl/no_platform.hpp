#pragma once
// Why the ICD loader found no OpenCL platform, for the one line a user sees. It is the machine's state, not the
// user's input (exit 1), and the cause is rarely "no driver": PoCL, for one, registers no platform when its kernel
// cache folder cannot be created — a read-only $HOME or a bad XDG_CACHE_HOME looks like a missing driver.
#include <string>

namespace clr::cl {

// "…: <cause>; <what to do>", naming the folder or variable at fault.
std::string no_platform_cause();

// "" unless `platform_name` is PoCL's and its kernel cache folder (POCL_CACHE_DIR, else XDG_CACHE_HOME/pocl, else
// ~/.cache/pocl) cannot be made or written; then the line that says so. PoCL registers its platform even where the
// folder is a file, and only fails each kernel build later with an empty build log.
std::string pocl_cache_cause(const std::string& platform_name);

}  // namespace clr::cl
