#pragma once
// Which PLY properties become mesh attributes, by Mitsuba 3's naming rules (its ply plugin): a colour r g b [a]
// (or red green blue [alpha]) becomes `<element>_color`; other properties named `<prefix>_<postfix>`, consecutive
// and sharing a prefix, with one-letter postfixes running through one of x y z w, r g b a, 0 1 2 3 or 1 2 3 4,
// become `<element>_<prefix>` (`<element>_<prefix>_color` for r g b a), kept with 1 or 3 channels. Anything else
// (no postfix, a broken sequence, 2 or 4 channels, a prefix seen before) is no attribute, as in Mitsuba.
#include <cstddef>
#include <string>
#include <vector>

namespace clr::scene {

struct PlyAttribute {
  std::string name;                     // e.g. "vertex_color", "face_weight"
  std::vector<std::size_t> properties;  // the element's properties holding its channels, in order
};

// `element` is "vertex" or "face"; `names` are the element's property names, an empty one for a property that is
// never an attribute (a list, or one the reader already uses such as a position or texture coordinate).
std::vector<PlyAttribute> ply_attributes(const std::string& element, const std::vector<std::string>& names);

}  // namespace clr::scene
