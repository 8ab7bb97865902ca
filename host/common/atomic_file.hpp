#pragma once
// Writes a whole file under a temporary name and renames it into place: a crash or a failed write never leaves
// a partial file that looks complete (the CLI's rule for every output).
#include <filesystem>
#include <functional>
#include <string_view>

namespace clr {

// Calls `write(temp_path)` and renames the result onto `path`; removes the temporary on any failure.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write);
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace clr
