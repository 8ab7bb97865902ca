#include "common/atomic_file.hpp"

#include <unistd.h>

#include <fstream>
#include <stdexcept>

namespace clr {
namespace fs = std::filesystem;

void write_atomically(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  const fs::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
  try {
    if (path.has_parent_path()) fs::create_directories(path.parent_path());
    write(tmp);
    fs::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
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
