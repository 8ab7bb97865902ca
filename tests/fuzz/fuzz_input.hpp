#pragma once
// libFuzzer harnesses read files, not buffers (every reader takes a path): each input is written to a file of
// this process's own, whose name the harness chooses (an extension, a scene's folder).
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace clr::fuzz {

// The process's folder, removed when it exits (libFuzzer ends with exit(), which runs this destructor): CI machines
// otherwise gathered one folder per harness run in /tmp.
struct InputDir {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("clr_fuzz_" + std::to_string(::getpid()));
  InputDir() { std::filesystem::create_directories(path); }
  ~InputDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

inline std::filesystem::path write_input(const std::string& name, const std::uint8_t* data, std::size_t size) {
  static const InputDir dir;
  const auto path = dir.path / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

}  // namespace clr::fuzz
