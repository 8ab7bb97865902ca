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
  float near_clip = 1e-2f;
  int width = 768, height = 576;

  struct Ray {
    Vec3 origin, direction;  // direction is unit length
    float tnear;             // the near clip plane, as a distance along the ray
  };
  // (px, py) in pixel units: (0, 0) the top-left corner of the image, (width, height) the bottom-right.
  Ray ray(float px, float py) const;
  // Half-extents of the image plane at distance 1.
  Vec2 tan_half_fov() const;
  // The same camera with a film of another size (0 keeps the scene's): as in Mitsuba and Tungsten, the film defines
  // the aspect and the field of view holds along fov_axis, so the view widens or narrows; it is never squeezed.
  // Every image of a scene (reference, render, the guide's pixel, the sweep) is taken with this one model.
  Camera resized(int new_width, int new_height) const;
  // InputError "<what>: …" unless the camera can make rays: a finite origin within ±kMaxCoordinate, a finite,
  // non-degenerate view direction and a field of view in (0, 180) degrees.
  void validate(const std::string& what) const;
};

}  // namespace clr::scene
