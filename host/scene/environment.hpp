#pragma once
// Light from infinitely far away: Mitsuba's `constant` and `envmap` (lat-long image) emitters. The envmap is
// importance-sampled by a piecewise-constant density proportional to luminance · sin θ, and looked up with the
// same piecewise-constant reconstruction, so sample() and pdf() agree exactly.
#include <filesystem>
#include <vector>

#include "scene/frame.hpp"

namespace clr::scene {

class Environment {
 public:
  static Environment constant(const Rgb& radiance);
  static Environment envmap(const std::filesystem::path& path, float scale, const glm::mat4& to_world);

  // Radiance arriving from world direction `dir` (pointing away from the scene, towards the environment).
  Rgb eval(const Vec3& dir) const;
  struct Sample {
    Vec3 dir;
    Rgb radiance;
    float pdf;  // solid angle
  };
  Sample sample(const Vec2& u) const;
  float pdf(const Vec3& dir) const;

 private:
  Vec2 to_uv(const Vec3& local) const;
  float pixel_pdf(int x, int y) const;  // density in uv of the pixel (x, y)

  Rgb constant_{0.0f};
  int width_ = 0, height_ = 0;  // 0: constant
  std::vector<Rgb> pixels_;
  std::vector<float> row_cdf_;     // height + 1 entries
  std::vector<float> column_cdf_;  // per row, width + 1 entries
  std::vector<float> weights_;     // luminance · sin θ per pixel, normalised so that their mean is 1
  glm::mat3 to_world_{1.0f}, to_local_{1.0f};
};

}  // namespace clr::scene
