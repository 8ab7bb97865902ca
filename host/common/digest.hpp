#pragma once
// A 64-bit content digest (FNV-1a) of bytes and files: what a run records of the scene it was trained on, and what
// MPI ranks compare before they compute together. It tells copies from different files, not a guard against
// deliberate collisions — none of these inputs is adversarial.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace clr {

class Digest {
 public:
  Digest& add(std::string_view bytes);
  // Bytes of a file, streamed (meshes may be large); std::runtime_error naming it when it cannot be read.
  Digest& add_file(const std::filesystem::path& file);
  std::uint64_t value() const { return state_; }
  // 16 lower-case hex digits.
  std::string hex() const;

 private:
  std::uint64_t state_ = 0xcbf29ce484222325ull;
};

}  // namespace clr
