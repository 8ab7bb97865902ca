// PLY (Turk 1994): ascii, binary_little_endian and binary_big_endian; vertex x y z [nx ny nz] [u v | s t |
// texture_u texture_v], faces as index lists (polygons are fanned into triangles). Further vertex and face
// properties become mesh attributes by Mitsuba's naming rules (ply_attributes.hpp), their values as stored (Mitsuba
// 3 neither normalises nor gamma-decodes integer colours); a fanned polygon's triangles share its face attributes.
// Other elements are skipped.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "scene/mesh.hpp"
#include "scene/shapes/file_mesh.hpp"
#include "scene/shapes/ply_attributes.hpp"

namespace clr::scene {
namespace {

enum class Format { ascii, little, big };

struct Property {
  std::string name;
  std::string type;        // scalar type, or the item type of a list
  std::string count_type;  // empty unless a list
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

int type_size(const std::string& t, const std::filesystem::path& path) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  throw InputError(path.string() + ": PLY property type '" + t + "' unknown");
}

class Reader {
 public:
  Reader(std::istream& in, Format format, const std::filesystem::path& path) : in_(in), format_(format), path_(path) {}

  double read(const std::string& type) {
    if (format_ == Format::ascii) {
      double v;
      if (!(in_ >> v)) fail();
      return v;
    }
    const int size = type_size(type, path_);
    unsigned char b[8];
    if (!in_.read(reinterpret_cast<char*>(b), size)) fail();
    if ((format_ == Format::big) != (std::endian::native == std::endian::big)) std::reverse(b, b + size);
    auto get = [&]<typename T>(T) {
      T v;
      std::memcpy(&v, b, sizeof v);
      return double(v);
    };
    if (type == "char" || type == "int8") return get(std::int8_t{});
    if (type == "uchar" || type == "uint8") return get(std::uint8_t{});
    if (type == "short" || type == "int16") return get(std::int16_t{});
    if (type == "ushort" || type == "uint16") return get(std::uint16_t{});
    if (type == "int" || type == "int32") return get(std::int32_t{});
    if (type == "uint" || type == "uint32") return get(std::uint32_t{});
    if (type == "float" || type == "float32") return get(float{});
    return get(double{});
  }

 private:
  [[noreturn]] void fail() { throw InputError(path_.string() + ": PLY data ends early or is malformed"); }
  std::istream& in_;
  Format format_;
  std::filesystem::path path_;
};

std::uint64_t data_bytes(std::istream& in) {
  const auto here = in.tellg();
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(here);
  return std::uint64_t(end - here);
}

// A header may announce billions of elements; each takes at least some bytes of the data that follows (in ascii
// a digit and a separator per value, in binary its scalars and list counts), so counts the file cannot hold are
// refused before anything is read or allocated.
void check_counts(const std::vector<Element>& elements, Format format, std::uint64_t available,
                  const std::filesystem::path& path) {
  std::uint64_t needed = 0;
  for (const auto& e : elements) {
    std::uint64_t each = 0;
    for (const auto& p : e.properties)
      each +=
          format == Format::ascii ? 2 : std::uint64_t(type_size(p.count_type.empty() ? p.type : p.count_type, path));
    if (each == 0) continue;  // holds no data whatever its count (and load_ply skips it)
    const std::uint64_t at_most = (available - std::min(needed, available)) / each;
    if (e.count > at_most)
      throw InputError(path.string() + ": PLY header announces " + std::to_string(e.count) + " '" + e.name +
                       "' elements, more than the file's " + std::to_string(available) + " bytes of data can hold");
    needed += e.count * each;
  }
}

}  // namespace

Mesh load_ply(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": mesh file not found");
  std::string line;
  if (!std::getline(in, line) || line.substr(0, 3) != "ply") throw InputError(path.string() + ": not a PLY file");
  Format format = Format::ascii;
  std::vector<Element> elements;
  bool header_ended = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "end_header") {
      header_ended = true;
      break;
    }
    if (word == "format") {
      words >> word;
      if (word == "ascii")
        format = Format::ascii;
      else if (word == "binary_little_endian")
        format = Format::little;
      else if (word == "binary_big_endian")
        format = Format::big;
      else
        throw InputError(path.string() + ": PLY format '" + word + "' unknown");
    } else if (word == "element") {
      Element e;
      words >> e.name >> e.count;
      if (!words) throw InputError(path.string() + ": malformed PLY element line '" + line + "'");
      // A second 'vertex' element would append vertices that the first's faces never meant, and a second
      // 'face' its triangles and attributes twice over.
      for (const auto& other : elements)
        if (other.name == e.name) throw InputError(path.string() + ": PLY element '" + e.name + "' is declared twice");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw InputError(path.string() + ": PLY property before any element");
      Property p;
      words >> p.type;
      if (p.type == "list") words >> p.count_type >> p.type;
      words >> p.name;
      if (!words) throw InputError(path.string() + ": malformed PLY property line '" + line + "'");
      type_size(p.type, path);
      if (!p.count_type.empty()) type_size(p.count_type, path);
      for (const auto& other : elements.back().properties)
        if (other.name == p.name)
          throw InputError(path.string() + ": PLY property '" + p.name + "' of element '" + elements.back().name +
                           "' is declared twice");
      elements.back().properties.push_back(p);
    } else if (word != "comment" && word != "obj_info" && !word.empty()) {
      throw InputError(path.string() + ": unexpected PLY header line '" + line + "'");
    }
  }

  if (!header_ended) throw InputError(path.string() + ": PLY header has no end_header line");
  check_counts(elements, format, data_bytes(in), path);

  Mesh m;
  Reader reader(in, format, path);
  for (const auto& e : elements) {
    if (e.properties.empty()) continue;  // nothing to read, however many the header counts
    const bool vertex = e.name == "vertex", face = e.name == "face";
    auto find = [&](std::initializer_list<const char*> names) {
      for (const char* n : names)
        for (std::size_t i = 0; i < e.properties.size(); ++i)
          if (e.properties[i].name == n) return int(i);
      return -1;
    };
    const int ix = find({"x"}), iy = find({"y"}), iz = find({"z"});
    const int inx = find({"nx"}), iny = find({"ny"}), inz = find({"nz"});
    const int iu = find({"u", "s", "texture_u", "texture_s"}), iv = find({"v", "t", "texture_v", "texture_t"});
    if (vertex && (ix < 0 || iy < 0 || iz < 0)) throw InputError(path.string() + ": PLY vertices lack x, y or z");
    const bool normals = vertex && inx >= 0 && iny >= 0 && inz >= 0, uvs = vertex && iu >= 0 && iv >= 0;
    // Properties that may carry attributes: the element's scalars, less those read as geometry above.
    std::vector<std::string> names;
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const int k = int(i);
      const bool geometry =
          vertex && (k == ix || k == iy || k == iz || (normals && (k == inx || k == iny || k == inz)) ||
                     (uvs && (k == iu || k == iv)));
      names.push_back(e.properties[i].count_type.empty() && !geometry ? e.properties[i].name : "");
    }
    const auto layout = vertex || face ? ply_attributes(e.name, names) : std::vector<PlyAttribute>{};
    const std::size_t first_attribute = m.attributes.size();
    for (const auto& a : layout) m.attributes.push_back({a.name, int(a.properties.size()), {}});
    std::vector<double> values(e.properties.size());
    std::vector<double> list;
    for (std::size_t n = 0; n < e.count; ++n) {
      const std::size_t triangles_before = m.triangles.size();
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        const auto& prop = e.properties[p];
        if (prop.count_type.empty()) {
          values[p] = reader.read(prop.type);
          continue;
        }
        const double count = reader.read(prop.count_type);
        if (!(count >= 0 && count < 1e6)) throw InputError(path.string() + ": PLY list length out of range");
        list.resize(std::size_t(count));
        for (auto& x : list) x = reader.read(prop.type);
        if (face && (prop.name == "vertex_indices" || prop.name == "vertex_index")) {
          for (double x : list) {
            if (!(x >= 0 && x < 4294967295.0)) throw InputError(path.string() + ": PLY face index out of range");
            // An index stored as a float or written with a fraction would be cut to another vertex's index.
            if (x != std::floor(x))
              throw InputError(path.string() + ": PLY face index " + std::to_string(x) + " is not a whole number");
          }
          for (std::size_t k = 2; k < list.size(); ++k)
            m.triangles.push_back({std::uint32_t(list[0]), std::uint32_t(list[k - 1]), std::uint32_t(list[k])});
        }
      }
      if (vertex) {
        m.positions.emplace_back(float(values[ix]), float(values[iy]), float(values[iz]));
        if (normals) m.normals.emplace_back(float(values[inx]), float(values[iny]), float(values[inz]));
        // As stored, as Mitsuba 3 reads them (only obj's v is flipped, there and here).
        if (uvs) m.uvs.emplace_back(float(values[iu]), float(values[iv]));
      }
      // One value per vertex, or per triangle the face was fanned into.
      const std::size_t copies = face ? m.triangles.size() - triangles_before : 1;
      for (std::size_t k = 0; k < layout.size(); ++k)
        for (std::size_t c = 0; c < copies; ++c)
          for (const std::size_t p : layout[k].properties)
            m.attributes[first_attribute + k].values.push_back(float(values[p]));
    }
  }
  m.check_structure(path.string());
  return m;
}

}  // namespace clr::scene

namespace clr::scene::loader {
ShapePlugin read_ply(Context& ctx, const Props& p) {
  return file_mesh(p, load_ply(ctx.file(p, "filename", "mesh file")));
}
}  // namespace clr::scene::loader
