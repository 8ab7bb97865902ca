#pragma once
// The XML side of the Mitsuba loader: parsed files, element positions as "file:line", `$name` substitution, the
// camelCase → snake_case upgrade of scene versions before 2.0, and typed values (numbers, colours, transforms).
// Every failure is an InputError naming the file, the line and the element.
#include <filesystem>
#include <map>
#include <memory>
#include <pugixml.hpp>
#include <set>
#include <string>
#include <vector>

#include "scene/frame.hpp"

namespace clr::scene::xml {

struct Source {
  std::filesystem::path path;
  pugi::xml_document doc;
  std::vector<std::size_t> line_starts;  // byte offsets where lines begin: pugixml reports offsets, users want lines
  int version_major = 3;

  int line_of(std::ptrdiff_t offset) const;
};

// $name parameters (Mitsuba's <default>s and -D key=value), and the names a substitution has used: Mitsuba refuses
// a given parameter that the scene never uses, and so do we.
struct Parameters {
  std::map<std::string, std::string> values;
  mutable std::set<std::string> used;
};

// An element together with the file it came from, so that every message can say where it is.
struct Node {
  pugi::xml_node xml;
  const Source* source;
  const Parameters* parameters;  // for $name substitution

  std::string tag() const { return xml.name(); }
  // "file:line: <tag name=".." type="..">"
  std::string where() const;
  [[noreturn]] void fail(const std::string& problem) const;

  bool has(const char* attribute) const { return !xml.attribute(attribute).empty(); }
  // The attribute with $parameters substituted (and, for `name`, upgraded to snake_case in old scenes); fails
  // when it is missing.
  std::string attr(const char* attribute) const;
  std::string attr_or(const char* attribute, const std::string& fallback) const;
  std::vector<Node> children() const;  // element children only (comments and text skipped)

  float number(const char* attribute) const;  // whole string must be a finite number
  float number_or(const char* attribute, float fallback) const;
  std::vector<float> numbers(const char* attribute) const;  // separated by commas and/or spaces
  // <rgb>/<srgb> (three values, one, or "#rrggbb"), <spectrum> (one value or wavelength:value pairs), <float>.
  Rgb color() const;
  Rgb spectrum() const;         // wavelength:value pairs → linear sRGB (scene/xml/spectrum.hpp)
  bool inside_emitter() const;  // an <emitter> encloses the element: its colours are emission
  Vec3 vector3() const;         // <point>/<vector>: x/y/z attributes or value="x, y, z"
  glm::mat4 transform() const;  // <transform>: its children applied in document order
};

// Reads and parses a file (InputError "file: not found" / "file:line: malformed XML: ...").
std::unique_ptr<Source> parse_file(const std::filesystem::path& path);

// camelCase → snake_case as Mitsuba 3 upgrades old scenes: a lower-case letter or digit followed by an upper-case
// one gets an underscore, then everything is lower-cased (toWorld → to_world, intIOR → int_ior).
std::string snake_case(const std::string& name);

}  // namespace clr::scene::xml
