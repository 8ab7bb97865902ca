#pragma once
// Writes a whole file under a temporary name and renames it into place: a crash or a failed write never leaves
// a partial file that looks complete (the CLI's rule for every output).
//
// Only a regular file (or nothing) may be replaced that way: renaming over a device, FIFO or socket would put a
// regular file in its place (`-o /dev/null` would delete the null device for everyone). Such a target is written
// through instead: the whole output is first made in a temporary file, then copied into the target, so a failed
// write still sends nothing. A symbolic link is followed, so the link stays and the file it names is replaced.
#include <filesystem>
#include <functional>
#include <string_view>

namespace clr {

// Calls `write(temp_path)` and renames the result onto `path` (or copies it into a non-regular `path`); removes
// the temporary on any failure. A directory at `path` is an InputError.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write);
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

// InputError "<option>: <path> is a directory" when an output cannot be written there. Commands check their
// outputs before the work that produces them, so a typo does not cost a whole render.
void require_output_path(const std::filesystem::path& path, const std::string& option);

}  // namespace clr
