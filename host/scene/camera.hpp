#pragma once
// Mitsuba's `perspective` sensor: a pinhole looking down +z of its to_world frame, +y up and +x to the image's
// left (Mitsuba's convention), with the field of view measured along `fov_axis`.
#include <string>

#include "scene/frame.hpp"

namespace clr::scene {

struct Camera {
  enum class FovAxis { x, y, diagonal, smaller, larger };
  glm::mat4 to_world{1.0f};
  float fov_degrees = 45.0f;
  FovAxis fov_axis = FovAxis::x;
  float near_clip = 1e-2f, far_clip = 1e4f;  // distances along the view axis (Mitsuba's defaults)
  int width = 768, height = 576;

  struct Ray {
    Vec3 origin, direction;  // direction is unit length
    float tnear, tfar;       // the near and far clip planes, as distances along the ray
  };
  // (px, py) in pixel units: (0, 0) the top-left corner of the image, (width, height) the bottom-right.
  Ray ray(float px, float py) const;
  // Half-extents of the image plane at distance 1.
  Vec2 tan_half_fov() const;
};

}  // namespace clr::scene
