#pragma once
// libFuzzer harnesses read files, not buffers (every reader takes a path): each input is written to a file of
// this process's own, whose name the harness chooses (an extension, a scene's folder).
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace clr::fuzz {

inline std::filesystem::path write_input(const std::string& name, const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("clr_fuzz_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

}  // namespace clr::fuzz
