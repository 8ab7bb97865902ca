#pragma once
// Lights without area, which no ray hits and only next-event estimation reaches: Mitsuba's `point`, `spot`,
// `directional` and `projector` emitters.
#include <limits>
#include <optional>

#include "scene/camera.hpp"
#include "scene/texture.hpp"

namespace clr::scene {

struct DeltaLight {
  enum class Kind { point, spot, directional, projector };
  Kind kind = Kind::point;
  Vec3 position{0.0f};       // point, spot, projector
  Vec3 direction{0, 0, 1};   // directional: where the light travels
  glm::mat4 to_local{1.0f};  // spot, projector: world → the light's frame (looking down +z)
  Rgb intensity{1.0f};       // point, spot: W/sr; directional: irradiance; projector: the `scale`
  // spot: linear falloff between the beam width and the cutoff (radians), an optional projected texture.
  float cutoff = 0, beam_width = 0;
  std::optional<Texture> texture;  // spot: `texture`; projector: `irradiance`
  Camera projection;               // projector: the perspective mapping of its image (a camera's)

  struct Arrival {
    Vec3 direction;  // unit, from the lit point towards the light
    float distance;  // infinity for a directional light
    Rgb radiance;    // what arrives, such that the reflected radiance is f·cos·radiance (a delta in direction)
  };
  // Light arriving at `p`; black where the light does not reach (outside a cone or a projected image).
  Arrival arrive(const Vec3& p) const;
};

}  // namespace clr::scene
