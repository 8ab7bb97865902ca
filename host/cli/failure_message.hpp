#pragma once
// The one stderr line of a runtime failure (exit 1, docs/design.md §4). Running out of device or host memory is the
// failure a user can most often fix themselves, so its line says which option of the command to lower.
#include <exception>
#include <string>

namespace clr::cli {

// `command` is the subcommand's name ("train", "render", …; "" for the main job). The exception's own text, plus
// for an out-of-memory error (CL_OUT_OF_RESOURCES, CL_MEM_OBJECT_ALLOCATION_FAILURE, CL_INVALID_BUFFER_SIZE,
// CL_OUT_OF_HOST_MEMORY, std::bad_alloc) what to lower.
std::string failure_message(const std::exception& e, const std::string& command);

}  // namespace clr::cli
