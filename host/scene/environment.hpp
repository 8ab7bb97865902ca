#pragma once
// Light from infinitely far away: Mitsuba's `constant`, `envmap` (lat-long image) and `sunsky` emitters. The envmap is
// looked up bilinearly between texels placed as Mitsuba 3 places them — columns at texel centres, rows from pole to
// pole (a nearest-texel lookup lit a diffuse sphere 0.3 % darker than Mitsuba and showed its texels; texel-centred
// rows left a plane under a map 0.4 % dark) — and importance-sampled by a piecewise-constant density proportional to
// luminance · sin θ over cells of the image's grid; sample() reports that density, which pdf() gives too, and the
// bilinear radiance. A sunsky is
// evaluated analytically; its sky is sampled by such a table of itself and its sun by a direction uniform in the
// disc's cone, each by its share of the power.
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "scene/delta_light.hpp"
#include "scene/frame.hpp"
#include "scene/sunsky.hpp"

namespace clr::scene {

class Environment {
 public:
  static Environment constant(const Rgb& radiance);
  static Environment envmap(const std::filesystem::path& path, float scale, const glm::mat4& to_world);
  static Environment sunsky(const SunSky& model, const glm::mat4& to_world);

  // Radiance arriving from world direction `dir` (pointing away from the scene, towards the environment); without a
  // sunsky's sun where `sun` is false.
  Rgb eval(const Vec3& dir, bool sun = true) const;
  // A sunsky's sun as a directional light of its irradiance (nullopt: no sun): what training takes it as by
  // next-event estimation, which no 0.27° disc hit by chance could replace (its radiance is ~10⁵ times the sky's).
  std::optional<DeltaLight> sun_as_directional() const;
  struct Sample {
    Vec3 dir;
    Rgb radiance;
    float pdf;  // solid angle
  };
  Sample sample(const Vec2& u) const;
  float pdf(const Vec3& dir) const;

 private:
  void set_to_world(const glm::mat4& to_world);
  // The sampling table from a luminance per cell of the image's grid; returns Σ luminance · sin θ over the cells
  // (0: all black, no table).
  double build_table(const std::vector<float>& cell_luminance);
  Sample sample_table(const Vec2& u) const;
  float pdf_table(const Vec3& dir) const;
  Vec2 to_uv(const Vec3& local) const;
  Rgb lookup(const Vec2& uv) const;     // bilinear, wrapping around in u, clamped at the poles
  float pixel_pdf(int x, int y) const;  // density in uv of the pixel (x, y)

  Rgb constant_{0.0f};
  int width_ = 0, height_ = 0;  // 0: constant
  std::vector<Rgb> pixels_;
  std::vector<float> row_cdf_;     // height + 1 entries
  std::vector<float> column_cdf_;  // per row, width + 1 entries
  std::vector<float> weights_;     // luminance · sin θ per pixel, normalised so that their mean is 1
  // to_world need not be a rotation (Mitsuba takes any matrix, a `rotate` about an axis not of unit length
  // included): directions are normalised after it, and the densities carry the Jacobian of that map of the sphere.
  glm::mat3 to_world_{1.0f}, to_local_{1.0f};
  float jacobian_scale_ = 1;              // |det to_local|
  std::shared_ptr<const SunSky> sunsky_;  // analytic radiance; pixels_ hold its sky for the table
  float sun_probability_ = 0;             // of drawing the sun's cone rather than the table
};

}  // namespace clr::scene
