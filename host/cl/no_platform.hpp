#pragma once
// Why the ICD loader found no OpenCL platform, for the one line a user sees. It is the machine's state, not the
// user's input (exit 1), and the cause is rarely "no driver": PoCL, for one, registers no platform when its kernel
// cache folder cannot be created — a read-only $HOME or a bad XDG_CACHE_HOME looks like a missing driver.
#include <string>

namespace clr::cl {

// "…: <cause>; <what to do>", naming the folder or variable at fault.
std::string no_platform_cause();

}  // namespace clr::cl
