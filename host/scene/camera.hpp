#pragma once
// Mitsuba's projective sensors, looking down +z of their to_world frame, +y up and +x to the image's left
// (Mitsuba's convention): `perspective` (a pinhole, the field of view measured along `fov_axis`), `thinlens` (the
// same with a circular aperture focused at `focus_distance`) and `orthographic` (parallel rays through the
// to_world image of [-1, 1] × [-h/w, h/w]).
#include <optional>
#include <span>
#include <string>

#include "scene/frame.hpp"
#include "scene/pixel_filter.hpp"

namespace clr::scene {

struct Camera {
  enum class FovAxis { x, y, diagonal, smaller, larger };
  enum class Projection { perspective, orthographic };
  Projection projection = Projection::perspective;
  float aperture_radius = 0;  // > 0: a thin lens
  float focus_distance = 0;   // thin lens: the depth (along +z) that is sharp
  glm::mat4 to_world{1.0f};
  float fov_degrees = 45.0f;
  FovAxis fov_axis = FovAxis::x;
  float near_clip = 1e-2f, far_clip = 1e4f;  // distances along the view axis (Mitsuba's defaults)
  // Mitsuba's principal_point_offset_x/y (perspective): the image plane shifted by these fractions of the film's
  // width and height (+x towards the image's right, +y down), as a lens shift; the mitsuba-blender exporter writes
  // them on every camera.
  Vec2 principal_point_offset{0.0f};
  int width = 768, height = 576;
  // The film's reconstruction filter: where in and around a pixel its samples fall, and their weights.
  PixelFilter filter;

  struct Ray {
    Vec3 origin, direction;  // direction is unit length
    float tnear, tfar;       // the near and far clip planes, as distances along the ray
  };
  // (px, py) in pixel units: (0, 0) the top-left corner of the image, (width, height) the bottom-right. `lens`
  // in [0, 1)² chooses the point on a thin lens' aperture (its centre at (0.5, 0.5)); pinholes ignore it.
  Ray ray(float px, float py, const Vec2& lens = Vec2(0.5f)) const;
  // A sample of pixel (x, y): its film position, drawn from the filter around the pixel's centre and kept on the
  // film, and the weight it carries into the pixel's mean. The box filter (radius 0.5) draws two numbers from `rng`, as
  // x + u, y + v.
  struct PixelSample {
    float px, py, weight;
  };
  PixelSample pixel_sample(std::size_t x, std::size_t y, Pcg32& rng) const;
  // Half-extents of the image plane at distance 1.
  Vec2 tan_half_fov() const;
  // The same camera with a film of another size (0 keeps the scene's): as in Mitsuba and Tungsten, the film defines
  // the aspect and the field of view holds along fov_axis, so the view widens or narrows; it is never squeezed.
  // Every image of a scene (reference, render, the guide's pixel, the sweep) is taken with this one model.
  Camera resized(int new_width, int new_height) const;
  // InputError "<what>: …" unless the camera can make rays: a finite origin within ±kMaxCoordinate, a finite,
  // non-degenerate view direction and a field of view in (0, 180) degrees.
  void validate(const std::string& what) const;
  // Another pinhole view of the same film: origin, target and up (9 numbers), then the vertical field of view in
  // degrees (`render --camera`, the Python module's `camera=`). InputError "<what>: …" when they make no view.
  Camera pinhole_view(std::span<const float> view, const std::string& what) const;
};

// Mitsuba's look-at frame as a to_world matrix: +z towards the target, +x = up × z (the image's left), +y the image's
// up; nullopt when the target is the origin or up is parallel to the view.
std::optional<glm::mat4> look_at(const Vec3& origin, const Vec3& target, const Vec3& up);

}  // namespace clr::scene
