#include "common/atomic_file.hpp"

#include <unistd.h>

#include <fstream>
#include <stdexcept>

#include "common/error.hpp"

namespace clr {
namespace fs = std::filesystem;
namespace {

// Runs `write` on `tmp` and hands the finished file to `place`; the temporary never outlives a failure.
void write_then(const fs::path& tmp, const std::function<void(const fs::path&)>& write,
                const std::function<void()>& place) {
  try {
    write(tmp);
    place();
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

// Copies a finished temporary into a target that must not be replaced (a device, FIFO, socket).
void copy_into(const fs::path& from, const fs::path& to) {
  std::ifstream in(from, std::ios::binary);
  std::ofstream out(to, std::ios::binary);
  if (!out) throw std::runtime_error("cannot open " + to.string() + " for writing");
  out << in.rdbuf();
  out.flush();
  if (!out || !in) throw std::runtime_error("writing " + to.string() + " failed");
}

}  // namespace

void write_atomically(const fs::path& requested, const std::function<void(const fs::path&)>& write) {
  std::error_code ec;
  // A link's target is what the user means to overwrite; renaming onto the link itself would replace the link.
  const fs::path path =
      fs::is_symlink(requested, ec) && fs::exists(requested, ec) ? fs::canonical(requested) : requested;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) throw InputError("output " + requested.string() + " is a directory");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // The target's folder may not take new files (/dev): the temporary goes to the system's temporary folder.
    const fs::path tmp = fs::temp_directory_path() /
                         ("clradiosity-" + std::to_string(::getpid()) + "-" + path.filename().string() + ".tmp");
    write_then(tmp, write, [&] {
      copy_into(tmp, path);
      fs::remove(tmp);
    });
    return;
  }
  const fs::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  write_then(tmp, write, [&] { fs::rename(tmp, path); });
}

void require_output_path(const fs::path& path, const std::string& option) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(option + ": output " + path.string() + " is a directory");
}

void write_text_atomically(const fs::path& path, std::string_view text) {
  write_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(text.data(), std::streamsize(text.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path.string());
  });
}

}  // namespace clr
