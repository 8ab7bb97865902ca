#pragma once
// What a scene may cost this machine's memory, weighed before it is spent: a shape's triangles (with Embree's copy
// and BVH), its instances' copies, the pixels of its textures and environment maps. The loader charges each part as
// soon as its size is known — an image from its header, a compressed mesh from its counts, before either is
// decoded — and refuses the part that would cross the limit, naming it, rather than letting the allocator (or the
// OOM killer) stop the command halfway through.
#include <array>
#include <cstdint>
#include <string>

namespace clr::scene {

// Bytes each part holds once loaded and traced (measured on Embree 3.13's high-quality BVH: a 262 144-triangle
// sphere with normals and uvs took 38 MB, ~146 bytes a triangle).
inline constexpr std::uint64_t kBytesPerTriangle = 120;         // indices, BVH, Embree's copy
inline constexpr std::uint64_t kBytesPerVertex = 48;            // position, normal, uv, Embree's padded copy
inline constexpr std::uint64_t kBytesPerExactShape = 512;       // the shape's record and its user primitive
inline constexpr std::uint64_t kBytesPerTexel = 12;             // float RGB
inline constexpr std::uint64_t kBytesPerEnvironmentTexel = 24;  // float RGB and the sampling tables

class MemoryBudget {
 public:
  enum class Part { geometry, images };

  // The limit: CLRADIOSITY_MEMORY_LIMIT (bytes, or with a K, M, G or T suffix: binary multiples), else three
  // quarters of the machine's physical memory. InputError naming the variable when it is no positive size.
  MemoryBudget();

  // InputError "<what> would bring the scene to about …, more than its limit of …" unless `bytes` more fit; else
  // counts them.
  void charge(std::uint64_t bytes, Part part, const std::string& what);
  // charge's check alone: whether `bytes` more would fit (before reading what they will hold).
  void require(std::uint64_t bytes, Part part, const std::string& what) const;
  std::uint64_t limit() const { return limit_; }

 private:
  std::uint64_t limit_ = 0;
  bool from_environment_ = false;
  std::array<std::uint64_t, 2> used_{};
};

// A size as "1.5 GB", "300 MB" or "under 1 MB" (binary multiples), for messages.
std::string human_bytes(std::uint64_t bytes);

}  // namespace clr::scene
