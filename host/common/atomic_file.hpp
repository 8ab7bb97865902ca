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
#include <vector>

namespace clr {

// Calls `write(temp_path)` and renames the result onto `path` (or copies it into a non-regular `path`); removes
// the temporary on any failure. A directory at `path` is an InputError.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write);
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

// Records and caches (run and sweep records, logs, checkpoints, the GEMM probe cache) are read back later, so they
// are files, never written through a device or FIFO as an output may be: InputError "<what> <path> is not a
// regular file …" when something else stands at `path` (a FIFO there would block the writer for good).
void require_file_target(const std::filesystem::path& path, const std::string& what);
void write_record_atomically(const std::filesystem::path& path, std::string_view text, const std::string& what);

// InputError "<option>: …" naming the path when an output cannot be written there: a directory, a parent that is a
// file (/etc/hostname/x), a folder that refuses new files (read-only, /proc). Commands check their outputs before
// the work that produces them, so a typo does not cost a whole render.
void require_output_path(const std::filesystem::path& path, const std::string& option);

// A command's outputs, checked together before its work: each as require_output_path does, and none the same file
// as another of them or as one of the command's `inputs` — writing it would silently replace that file. Identity
// is the device and inode after links are followed (a symlink to the scene is the scene), or the absolute path of
// an output that does not exist yet. Outputs that are devices or FIFOs are written through and may repeat.
struct Output {
  std::filesystem::path path;  // empty: the option was not given
  std::string option;          // "-o", "--png", …
};
void require_outputs(const std::vector<Output>& outputs, const std::vector<std::filesystem::path>& inputs);

// Creates and removes a probe file in `dir`, the way write_atomically will create its temporary there: InputError
// "<what> <dir>: <reason>" when that fails for a reason of the path (permissions, read-only, not a directory), a
// std::runtime_error when the system is at fault (a full disk, an I/O error).
void require_writable_directory(const std::filesystem::path& dir, const std::string& what);

}  // namespace clr
