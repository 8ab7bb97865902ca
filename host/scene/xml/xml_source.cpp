#include "scene/xml/xml_source.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "image/srgb.hpp"
#include "scene/camera.hpp"
#include "scene/xml/spectrum.hpp"

namespace clr::scene::xml {

namespace {
// Far beyond any real scene (Mitsuba's own nest a few levels: scene, shape, bsdf, bsdf, texture, transform).
constexpr int kMaxDepth = 64;
// Longest attribute value after $name substitution. Far beyond any real value, and it stops a chain of <default>s
// that each repeat the previous one (a "billion laughs") from growing exponentially.
constexpr std::size_t kMaxAttributeBytes = 1 << 16;
}  // namespace

int Source::line_of(std::ptrdiff_t offset) const {
  return int(
      std::upper_bound(line_starts.begin(), line_starts.end(), std::size_t(std::max<std::ptrdiff_t>(offset, 0))) -
      line_starts.begin());
}

std::unique_ptr<Source> parse_file(const std::filesystem::path& path) {
  const std::string text = read_input_text(path, "scene file");
  auto src = std::make_unique<Source>();
  src->path = path;
  src->line_starts.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') src->line_starts.push_back(i + 1);
  const auto result = src->doc.load_buffer(text.data(), text.size(), pugi::parse_default | pugi::parse_comments);
  if (!result)
    throw InputError(path.string() + ":" + std::to_string(src->line_of(result.offset)) +
                     ": malformed XML: " + result.description());
  // The loader walks nested plugins recursively (a twosided in a mask in a bumpmap...): a hostile file nested
  // 100 000 deep would overflow the stack. Measured here without recursion, before anything walks the tree.
  int depth = 0;
  for (pugi::xml_node n = src->doc.first_child(); n;) {
    if (depth > kMaxDepth)
      throw InputError(path.string() + ":" + std::to_string(src->line_of(n.offset_debug())) + ": <" + n.name() +
                       ">: elements nested deeper than " + std::to_string(kMaxDepth));
    // Depth-first order: a child, else the next sibling of the nearest ancestor that has one.
    if (n.first_child()) {
      n = n.first_child();
      ++depth;
      continue;
    }
    for (; n && !n.next_sibling(); --depth) n = n.parent();
    if (n) n = n.next_sibling();
  }
  return src;
}

std::string snake_case(const std::string& name) {
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (i > 0 && std::isupper((unsigned char)c) &&
        (std::islower((unsigned char)name[i - 1]) || std::isdigit((unsigned char)name[i - 1])))
      out += '_';
    out += char(std::tolower((unsigned char)c));
  }
  return out;
}

std::string Node::where() const {
  std::string s = source->path.string() + ":" + std::to_string(source->line_of(xml.offset_debug())) + ": <" + tag();
  for (const char* a : {"name", "type", "id"})
    if (has(a)) s += std::string(" ") + a + "=\"" + xml.attribute(a).value() + "\"";
  return s + ">";
}

void Node::fail(const std::string& problem) const { throw InputError(where() + ": " + problem); }

std::string Node::attr(const char* attribute) const {
  const auto a = xml.attribute(attribute);
  if (a.empty()) fail(std::string("missing attribute '") + attribute + "'");
  std::string v = a.value();
  // $name substitution (Mitsuba's <default> and command-line parameters).
  for (std::size_t pos = v.find('$'); pos != std::string::npos; pos = v.find('$', pos)) {
    std::size_t end = pos + 1;
    while (end < v.size() && (std::isalnum((unsigned char)v[end]) || v[end] == '_')) ++end;
    const std::string key = v.substr(pos + 1, end - pos - 1);
    const auto it = parameters->values.find(key);
    if (it == parameters->values.end()) fail("undefined parameter '$" + key + "'");
    parameters->used.insert(key);
    v.replace(pos, end - pos, it->second);
    pos += it->second.size();
    if (v.size() > kMaxAttributeBytes)
      fail(std::string("attribute '") + attribute + "' exceeds " + std::to_string(kMaxAttributeBytes) +
           " bytes after $parameter substitution");
  }
  if (std::string(attribute) == "name" && source->version_major < 2) v = snake_case(v);
  return v;
}

std::string Node::attr_or(const char* attribute, const std::string& fallback) const {
  return has(attribute) ? attr(attribute) : fallback;
}

std::vector<Node> Node::children() const {
  std::vector<Node> out;
  for (auto c : xml.children())
    if (c.type() == pugi::node_element) out.push_back({c, source, parameters});
  return out;
}

namespace {
bool parse_float(std::string_view s, float& out) {
  while (!s.empty() && std::isspace((unsigned char)s.front())) s.remove_prefix(1);
  while (!s.empty() && std::isspace((unsigned char)s.back())) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty() && std::isfinite(out);
}
}  // namespace

float Node::number(const char* attribute) const {
  const std::string v = attr(attribute);
  float f;
  if (!parse_float(v, f)) fail("malformed number '" + v + "'");
  return f;
}

float Node::number_or(const char* attribute, float fallback) const {
  return has(attribute) ? number(attribute) : fallback;
}

std::vector<float> Node::numbers(const char* attribute) const {
  std::string v = attr(attribute);
  std::replace(v.begin(), v.end(), ',', ' ');
  std::istringstream words(v);
  std::vector<float> out;
  for (std::string w; words >> w;) {
    float f;
    if (!parse_float(w, f)) fail("malformed number '" + w + "' in '" + attr(attribute) + "'");
    out.push_back(f);
  }
  return out;
}

Rgb Node::color() const {
  const std::string t = tag();
  if (t != "rgb" && t != "srgb" && t != "spectrum" && t != "float") fail("expected a colour (rgb, spectrum or float)");
  const std::string value = attr("value");
  // "#rrggbb" (Mitsuba 0.x): an 8-bit sRGB colour.
  if ((t == "rgb" || t == "srgb") && !value.empty() && value.front() == '#') {
    Rgb c;
    int consumed = 0;
    unsigned r = 0, g = 0, b = 0;
    if (value.size() != 7 || std::sscanf(value.c_str(), "#%2x%2x%2x%n", &r, &g, &b, &consumed) != 3 || consumed != 7)
      fail("malformed colour '" + value + "' (expected #rrggbb)");
    c = Rgb(float(r), float(g), float(b)) / 255.0f;
    for (int i = 0; i < 3; ++i) c[i] = image::srgb_to_linear(c[i]);
    return c;
  }
  if (t == "spectrum" && value.find(':') != std::string::npos) return spectrum();
  const auto v = numbers("value");
  if (v.size() != 1 && v.size() != 3) fail("a colour needs 1 or 3 values");
  // One value of a <spectrum> is a flat spectrum. Mitsuba 3's RGB variants turn it grey as a reflectance (under
  // D65) but, as emission, into illuminant E's linear sRGB (1.2048, 0.9483, 0.9089): warmer than a grey <rgb>
  // or <float> of the same value. A public scene lit so rendered 10–17 % off in red and blue. Mitsuba 0.x, whose
  // files declare an older version, kept it grey.
  if (t == "spectrum" && v.size() == 1 && source->version_major >= 2 && inside_emitter())
    return spectrum_to_rgb({kCieFirst, kCieLast}, {v[0], v[0]}, false, false);
  Rgb c = v.size() == 1 ? Rgb(v[0]) : Rgb(v[0], v[1], v[2]);
  if (t == "srgb")
    for (int i = 0; i < 3; ++i) c[i] = image::srgb_to_linear(c[i]);
  return c;
}

bool Node::inside_emitter() const {
  for (pugi::xml_node p = xml.parent(); p; p = p.parent())
    if (std::string(p.name()) == "emitter") return true;
  return false;
}

Rgb Node::spectrum() const {
  std::string v = attr("value");
  std::replace(v.begin(), v.end(), ',', ' ');
  std::istringstream words(v);
  std::vector<float> wavelengths, values;
  for (std::string w; words >> w;) {
    const auto colon = w.find(':');
    float l, x;
    if (colon == std::string::npos || !parse_float(std::string_view(w).substr(0, colon), l) ||
        !parse_float(std::string_view(w).substr(colon + 1), x))
      fail("malformed wavelength:value pair '" + w + "'");
    if (!wavelengths.empty() && !(l > wavelengths.back())) fail("wavelengths must increase");
    wavelengths.push_back(l);
    values.push_back(x);
  }
  if (wavelengths.size() < 2) fail("a spectrum needs at least two wavelength:value pairs");
  // Emission and the unbounded optical constants may exceed 1; reflectances are clamped to [0, 1] (Mitsuba).
  // Only emission is integrated without the D65 white (Mitsuba 3's RGB variants).
  const bool emission = inside_emitter();
  const std::string name = attr_or("name", "");
  const bool bounded = !emission && name != "eta" && name != "k" && name != "int_ior" && name != "ext_ior";
  return spectrum_to_rgb(wavelengths, values, bounded, !emission);
}

Vec3 Node::vector3() const {
  if (has("value")) {
    const auto v = numbers("value");
    if (v.size() != 3) fail("expected 3 values");
    return {v[0], v[1], v[2]};
  }
  return {number_or("x", 0.0f), number_or("y", 0.0f), number_or("z", 0.0f)};
}

glm::mat4 Node::transform() const {
  if (tag() != "transform") fail("expected a <transform>");
  glm::mat4 m(1.0f);
  for (const Node& op : children()) {
    const std::string t = op.tag();
    glm::mat4 step(1.0f);
    if (t == "matrix") {
      const auto v = op.numbers("value");
      if (v.size() != 16 && v.size() != 9) op.fail("a matrix needs 16 (4×4) or 9 (3×3) values");
      const int n = v.size() == 16 ? 4 : 3;
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) step[c][r] = v[std::size_t(r * n + c)];  // row-major text, column-major glm
    } else if (t == "translate") {
      step = glm::translate(glm::mat4(1.0f), op.vector3());
    } else if (t == "scale") {
      Vec3 s;
      if (op.has("value")) {
        const auto v = op.numbers("value");
        if (v.size() != 1 && v.size() != 3) op.fail("scale needs 1 or 3 values");
        s = v.size() == 1 ? Vec3(v[0]) : Vec3(v[0], v[1], v[2]);
      } else {
        s = {op.number_or("x", 1.0f), op.number_or("y", 1.0f), op.number_or("z", 1.0f)};
      }
      step = glm::scale(glm::mat4(1.0f), s);
    } else if (t == "rotate") {
      Vec3 a = op.vector3();
      if (!(glm::length(a) > 0)) op.fail("rotation axis is zero");
      // Rodrigues' formula c·I + (1 − c)·a·aᵀ + s·[a]×. Mitsuba 0.6 normalised the axis; Mitsuba 2 and 3 use it as
      // given, so that an axis of another length also scales (one public scene looks 8 % different otherwise).
      if (source->version_major < 2) a = glm::normalize(a);
      const float angle = op.number("angle") * kPi / 180.0f, c = std::cos(angle), s = std::sin(angle);
      const glm::mat3 cross(0, a.z, -a.y, -a.z, 0, a.x, a.y, -a.x, 0);  // column-major [a]×
      step = glm::mat4(c * glm::mat3(1.0f) + (1.0f - c) * glm::outerProduct(a, a) + s * cross);
    } else if (t == "lookat" || t == "look_at" || t == "lookAt") {
      auto point = [&](const char* a) {
        const auto v = op.numbers(a);
        if (v.size() != 3) op.fail(std::string(a) + " needs 3 values");
        return Vec3(v[0], v[1], v[2]);
      };
      const Vec3 origin = point("origin"), target = point("target");
      const Vec3 dir = target - origin;
      // Without `up`, Mitsuba takes the first tangent of its orthonormal basis around the view direction (Duff et
      // al. 2017).
      Vec3 up(0, 1, 0);
      if (op.has("up")) {
        up = point("up");
      } else if (glm::length(dir) > 0) {
        const Vec3 n = glm::normalize(dir);
        const float sign = std::copysign(1.0f, n.z), a = -1.0f / (sign + n.z), b = n.x * n.y * a;
        up = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
      }
      const auto frame = look_at(origin, target, up);
      if (!frame) op.fail("degenerate lookat (up parallel to view)");
      step = *frame;
    } else {
      op.fail("unsupported transform operation");
    }
    m = step * m;
  }
  return m;
}

}  // namespace clr::scene::xml
