#pragma once
// A texture's `to_uv` transform, or Mitsuba 0.x's uscale/vscale/uoffset/voffset spelling of the same map.
#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {

inline UvTransform read_uv_transform(const Props& p) {
  UvTransform t;
  const glm::mat4 m = p.transform("to_uv");
  t.linear = glm::mat2(m[0][0], m[0][1], m[1][0], m[1][1]);
  t.offset = Vec2(m[3][0], m[3][1]);
  const Vec2 scale(p.number("uscale", 1.0f), p.number("vscale", 1.0f));
  const Vec2 offset(p.number("uoffset", 0.0f), p.number("voffset", 0.0f));
  t.linear = glm::mat2(scale.x, 0, 0, scale.y) * t.linear;
  t.offset = scale * t.offset + offset;
  return t;
}

}  // namespace clr::scene::loader
