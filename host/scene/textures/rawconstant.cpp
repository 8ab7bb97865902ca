// Mitsuba's `rawconstant` texture: a value used as given (no colour conversion), e.g. a normal map's constant.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {
Texture read_rawconstant(Context&, const Props& p) {
  if (!p.has("value")) p.node.fail("missing property 'value'");
  const Node& v = p.expect("value", {"vector", "point", "rgb", "float"});
  if (v.tag() == "float") return Texture(Rgb(v.number("value")));
  if (v.tag() == "rgb") {
    const auto n = v.numbers("value");
    if (n.size() != 1 && n.size() != 3) v.fail("expected 1 or 3 values");
    return Texture(n.size() == 1 ? Rgb(n[0]) : Rgb(n[0], n[1], n[2]));
  }
  return Texture(v.vector3());
}
}  // namespace clr::scene::loader
