#pragma once
// Checkpoint files (RUN_DIR/model.clr, docs/design.md §4): versioned and checksummed, written atomically.
//
//   offset 0   8 bytes  magic "CLRCKPT\n"
//          8   u32      format version (kCheckpointVersion)
//         12   u32      reserved, 0
//         16   u64      payload size in bytes
//         24   u64      FNV-1a 64 of the payload
//         32   payload: str config_json, u64 step, str rng_state, u32 tensor count,
//                       per tensor: str name, u64 float count, float32 values
//   str = u64 byte count + bytes. All integers and floats little-endian (the host's order on x86 and ARM).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace clr::nn {

inline constexpr std::uint32_t kCheckpointVersion = 1;

struct Checkpoint {
  std::string config_json;
  std::uint64_t step = 0;
  std::string rng_state;
  std::vector<std::pair<std::string, std::vector<float>>> tensors;

  // The tensor called `name` with exactly `count` values; throws InputError naming `path` otherwise.
  const std::vector<float>& tensor(const std::string& path, const std::string& name, std::size_t count) const;
  bool has(const std::string& name) const {
    for (const auto& t : tensors)
      if (t.first == name) return true;
    return false;
  }
};

// Writes under a temporary name, then renames over PATH: a crash never leaves a half-written PATH.
void write_checkpoint(const std::string& path, const Checkpoint& c);
// Throws InputError ("checkpoint FILE: …") when the file is missing, truncated, corrupt or of another version.
Checkpoint read_checkpoint(const std::string& path);

std::uint64_t fnv1a64(const void* data, std::size_t n);

}  // namespace clr::nn
