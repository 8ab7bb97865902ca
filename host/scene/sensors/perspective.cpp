// Mitsuba's `perspective` sensor: a pinhole. The field of view is `fov` along `fov_axis`, or a `focal_length`
// (default 50 mm) on 35 mm film, whose diagonal it spans.
#include <cmath>

#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {

// The clip planes and focus distance every projective camera of Mitsuba's reads.
void read_clip_planes(const Props& p, Camera& c) {
  c.near_clip = p.number("near_clip", 1e-2f);
  c.far_clip = p.number("far_clip", 1e4f);
  if (!(c.near_clip > 0)) p.expect("near_clip", {"float"}).fail("near_clip must be positive");
  if (!(c.near_clip < c.far_clip)) p.node.fail("near_clip must be smaller than far_clip");
  // The focal plane matters to a lens only (a pinhole is sharp everywhere); Mitsuba's default is the far plane.
  c.focus_distance = p.number("focus_distance", c.far_clip);
  if (!(c.focus_distance > 0)) p.expect("focus_distance", {"float"}).fail("focus_distance must be positive");
}

void read_fov(const Props& p, Camera& c) {
  if (p.has("fov") && p.has("focal_length")) p.node.fail("give either 'fov' or 'focal_length', not both");
  if (p.has("fov")) {
    c.fov_degrees = p.number("fov", 45.0f);
    if (!(c.fov_degrees > 0 && c.fov_degrees < 180)) p.expect("fov", {"float"}).fail("fov must lie in (0, 180)");
    const std::string axis = p.string("fov_axis", "x");
    if (axis == "x")
      c.fov_axis = Camera::FovAxis::x;
    else if (axis == "y")
      c.fov_axis = Camera::FovAxis::y;
    else if (axis == "diagonal")
      c.fov_axis = Camera::FovAxis::diagonal;
    else if (axis == "smaller")
      c.fov_axis = Camera::FovAxis::smaller;
    else if (axis == "larger")
      c.fov_axis = Camera::FovAxis::larger;
    else
      p.expect("fov_axis", {"string"}).fail("unsupported fov_axis '" + axis + "'");
  } else {
    const Node* given = p.find("focal_length");
    std::string f = !given ? "50mm" : given->tag() == "string" ? given->attr("value") : std::string();
    if (given && given->tag() != "string") f = std::to_string(p.number("focal_length", 50.0f));
    if (f.ends_with("mm")) f.resize(f.size() - 2);
    char* end = nullptr;
    const float mm = std::strtof(f.c_str(), &end);
    if (f.empty() || *end != '\0' || !(mm > 0) || !std::isfinite(mm))
      given->fail("malformed focal_length (expected e.g. \"50mm\")");
    // 35 mm film is 36 × 24 mm; the focal length sets the angle its diagonal spans.
    c.fov_degrees = 2.0f * std::atan(std::sqrt(36.0f * 36.0f + 24.0f * 24.0f) / (2.0f * mm)) * 180.0f / kPi;
    c.fov_axis = Camera::FovAxis::diagonal;
  }
}

void read_perspective(Context&, const Props& p, Camera& c) {
  read_fov(p, c);
  read_clip_planes(p, c);
  for (const auto& [name, value] : {std::pair{"principal_point_offset_x", &c.principal_point_offset.x},
                                    std::pair{"principal_point_offset_y", &c.principal_point_offset.y}}) {
    *value = p.number(name, 0.0f);
    if (!std::isfinite(*value)) p.expect(name, {"float"}).fail(std::string(name) + " must be finite");
  }
  c.to_world = p.transform("to_world");
}

}  // namespace clr::scene::loader
