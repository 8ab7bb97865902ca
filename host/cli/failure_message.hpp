#pragma once
// The one stderr line of a runtime failure (exit 1, docs/design.md §4). Running out of device or host memory is the
// failure a user can most often fix themselves, so its line says which option of the command to lower.
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

#include "common/terminal_text.hpp"

namespace clr::cli {

// `command` is the subcommand's name ("train", "render", …; "" for the main job). The exception's own text, plus
// for an out-of-memory error (CL_OUT_OF_RESOURCES, CL_MEM_OBJECT_ALLOCATION_FAILURE, CL_INVALID_BUFFER_SIZE,
// CL_OUT_OF_HOST_MEMORY, std::bad_alloc) what to lower.
std::string failure_message(const std::exception& e, const std::string& command);

// A filesystem error that the path given caused (a name too long, a file where a folder must be, no permission) is
// bad input (exit 2), and its line is "<path>: <reason>" rather than the library's "filesystem error: status: …".
bool path_at_fault(const std::filesystem::filesystem_error& e);
std::string path_message(const std::filesystem::filesystem_error& e);

// Any stderr line, bounded: a word (a path, a value, an option's argument) longer than 256 bytes keeps its start
// and end around "…(N bytes)…", and the line at most 4 KiB — a 100 KB argument is never echoed whole, wherever a
// message quotes it.
// Control characters and newlines escaped first (terminal_safe), and no cut inside a UTF-8 character.
std::string bounded_line(std::string_view line);

using clr::terminal_safe;  // common/terminal_text.hpp

}  // namespace clr::cli
