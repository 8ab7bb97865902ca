// Mitsuba's `.serialized` meshes: a table of zlib-compressed shapes. Layout per shape: uint16 0x041C, uint16
// version (3 or 4), then a zlib stream holding uint32 flags, (v4) a NUL-terminated name, uint64 vertex and
// triangle counts, positions, optional normals/uvs/colours (float or double), and uint32 (or uint64) indices. The
// file ends with the shapes' offsets (uint64 in v4, uint32 in v3) and a uint32 count.
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "scene/memory_budget.hpp"
#include "scene/mesh.hpp"
#include "scene/shapes/file_mesh.hpp"

namespace clr::scene {
namespace {

enum : std::uint32_t { kNormals = 0x1, kUvs = 0x2, kColors = 0x8, kFaceNormals = 0x10, kDouble = 0x2000 };

class Inflated {
 public:
  Inflated(std::vector<unsigned char> data, std::string what) : data_(std::move(data)), what_(std::move(what)) {}
  template <typename T>
  T get() {
    if (pos_ + sizeof(T) > data_.size()) throw InputError(what_ + ": shape data ends early");
    T v;
    std::memcpy(&v, &data_[pos_], sizeof v);
    pos_ += sizeof v;
    return v;
  }
  float real(bool dbl) { return dbl ? float(get<double>()) : get<float>(); }
  std::uint64_t remaining() const { return data_.size() - pos_; }
  void skip(std::uint64_t n) { pos_ += std::size_t(std::min<std::uint64_t>(n, remaining())); }
  void skip_string() {
    while (get<char>() != 0) {
    }
  }

 private:
  std::vector<unsigned char> data_;
  std::string what_;
  std::size_t pos_ = 0;
};

// Inflates the stream at `offset`, stopping once `limit` bytes are out: a shape's header says how much data it has,
// and a stream that inflates to far more (a zlib bomb: 1 MB of it inflates to 1 GB) is never inflated beyond that.
std::vector<unsigned char> inflate_at(const std::string& file, std::size_t offset, const std::string& what,
                                      std::uint64_t limit) {
  z_stream z{};
  if (inflateInit(&z) != Z_OK) throw std::runtime_error("zlib: inflateInit failed");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(file.data() + offset));
  z.avail_in = uInt(file.size() - offset);
  std::vector<unsigned char> out;
  unsigned char chunk[1 << 16];
  int rc;
  do {
    z.next_out = chunk;
    z.avail_out = sizeof chunk;
    rc = inflate(&z, Z_NO_FLUSH);
    if (rc != Z_OK && rc != Z_STREAM_END) {
      inflateEnd(&z);
      throw InputError(what + ": corrupt compressed data");
    }
    out.insert(out.end(), chunk, chunk + (sizeof chunk - z.avail_out));
  } while (rc != Z_STREAM_END && out.size() < limit);
  inflateEnd(&z);
  return out;
}

}  // namespace

Mesh load_serialized(const std::filesystem::path& path, int shape_index,
                     const std::function<void(std::uint64_t)>& before_decoding) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": mesh file not found");
  std::ostringstream buf;
  buf << in.rdbuf();
  const std::string file = buf.str();
  const std::string what = path.string();
  auto read_at = [&]<typename T>(std::size_t at, T) {
    if (at + sizeof(T) > file.size()) throw InputError(what + ": truncated serialized file");
    T v;
    std::memcpy(&v, file.data() + at, sizeof v);
    return v;
  };
  if (file.size() < 8 || read_at(0, std::uint16_t{}) != 0x041C) throw InputError(what + ": not a serialized mesh");
  const auto version = read_at(2, std::uint16_t{});
  if (version != 3 && version != 4)
    throw InputError(what + ": unsupported serialized version " + std::to_string(version));
  const std::uint32_t count = read_at(file.size() - 4, std::uint32_t{});
  if (shape_index < 0 || std::uint32_t(shape_index) >= count)
    throw InputError(what + ": shape_index " + std::to_string(shape_index) + " out of range (the file holds " +
                     std::to_string(count) + ")");
  const std::size_t table_entry = version == 4 ? 8 : 4;
  // Checked before the subtraction below, which would otherwise wrap around to an offset anywhere in memory.
  if (count > (file.size() - 4) / table_entry)
    throw InputError(what + ": the file claims " + std::to_string(count) + " shapes, more than its size can index");
  const std::size_t table = file.size() - 4 - table_entry * count;
  const std::size_t offset = version == 4 ? std::size_t(read_at(table + 8 * std::size_t(shape_index), std::uint64_t{}))
                                          : read_at(table + 4 * std::size_t(shape_index), std::uint32_t{});
  if (offset + 4 >= file.size()) throw InputError(what + ": corrupt shape offset table");

  // The header first (flags, a name, the counts), then as much data as the counts call for and no more.
  constexpr std::uint64_t kHeaderBytes = 1 << 16;
  auto head = inflate_at(file, offset + 4, what, kHeaderBytes);
  Inflated h(head, what);
  const auto flags = h.get<std::uint32_t>();
  if (version == 4) h.skip_string();
  const auto nv = h.get<std::uint64_t>(), nt = h.get<std::uint64_t>();
  if (nv > (1ull << 31) || nt > (1ull << 31)) throw InputError(what + ": implausible vertex or triangle count");
  const bool dbl = (flags & kDouble) != 0;
  const std::uint64_t header_size = head.size() - h.remaining();
  // The counts must fit the data actually inflated before anything is sized by them: a 100-byte file claiming
  // 2^31 vertices would otherwise allocate 24 GiB.
  const bool wide = nv > 0xffffffffull;
  const std::uint64_t real = dbl ? 8 : 4, per_vertex = real * (3 + (flags & kNormals ? 3 : 0) + (flags & kUvs ? 2 : 0) +
                                                               (flags & kColors ? 3 : 0));
  const std::uint64_t data = nv * per_vertex + nt * 3 * (wide ? 8 : 4);
  // Counts that the compressed bytes could not hold even at zlib's best ratio (1032:1) are refused as the corrupt
  // file they are; the rest is weighed by what it will cost (the inflated data and the mesh made of it) before it
  // is inflated.
  const std::uint64_t compressed = file.size() - (offset + 4);
  if (data > compressed * 1032)
    throw InputError(what + ": shape claims " + std::to_string(nv) + " vertices and " + std::to_string(nt) +
                     " triangles, more than its " + std::to_string(compressed) + " bytes of compressed data can hold");
  if (before_decoding) before_decoding(data + nt * kBytesPerTriangle + nv * kBytesPerVertex);
  Inflated s(
      head.size() >= header_size + data ? std::move(head) : inflate_at(file, offset + 4, what, header_size + data),
      what);
  s.skip(header_size);
  if (data > s.remaining())
    throw InputError(what + ": shape claims " + std::to_string(nv) + " vertices and " + std::to_string(nt) +
                     " triangles, more than its " + std::to_string(s.remaining()) + " bytes of data hold");
  Mesh m;
  m.positions.resize(nv);
  for (auto& p : m.positions) p = {s.real(dbl), s.real(dbl), s.real(dbl)};
  if (flags & kNormals) {
    m.normals.resize(nv);
    for (auto& n : m.normals) n = {s.real(dbl), s.real(dbl), s.real(dbl)};
  }
  if (flags & kUvs) {
    m.uvs.resize(nv);
    // As stored: Mitsuba 3 flips no serialized texture coordinates (only obj's, by `flip_tex_coords`); a flip
    // here inverted the checkerboards of its test scenes against its renders (mitsuba_corpus_peer_slow_test).
    for (auto& uv : m.uvs) {
      uv.x = s.real(dbl);
      uv.y = s.real(dbl);
    }
  }
  if (flags & kColors)
    for (std::uint64_t i = 0; i < 3 * nv; ++i) s.real(dbl);
  if (flags & kFaceNormals) m.normals.clear();
  m.triangles.resize(nt);
  for (auto& t : m.triangles)
    for (int c = 0; c < 3; ++c) {
      // Checked before narrowing: a 64-bit index past the vertices would otherwise wrap onto one of them.
      const std::uint64_t index = wide ? s.get<std::uint64_t>() : s.get<std::uint32_t>();
      if (index >= nv)
        throw InputError(what + ": triangle vertex index " + std::to_string(index) +
                         " is out of range (the shape has " + std::to_string(nv) + " vertices)");
      t[c] = std::uint32_t(index);
    }
  m.check_structure(what);
  return m;
}

}  // namespace clr::scene

namespace clr::scene::loader {
ShapePlugin read_serialized(Context& ctx, const Props& p) {
  const auto file = ctx.file(p, "filename", "mesh file");
  return file_mesh(p, load_serialized(file, p.integer("shape_index", 0), [&](std::uint64_t bytes) {
                     ctx.require_geometry(bytes, "mesh file " + file.string());
                   }));
}
}  // namespace clr::scene::loader
