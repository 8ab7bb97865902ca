#include "scene/xml/spectrum.hpp"

#include <algorithm>
#include <cmath>

namespace clr::scene {
namespace {
constexpr float kCieMin = 360.0f, kCieMax = 830.0f;
constexpr int kSteps = 1000;

// A Gaussian with different widths left and right of its mean.
float lobe(float lambda, float mean, float sigma_left, float sigma_right) {
  const float t = (lambda - mean) / (lambda < mean ? sigma_left : sigma_right);
  return std::exp(-0.5f * t * t);
}

// ∫ȳ over the integration grid, so that a flat spectrum of 1 has Y = 1 exactly.
float y_integral() {
  static const float integral = [] {
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) sum += cie1931_xyz(kCieMin + float(i) / float(kSteps - 1) * (kCieMax - kCieMin)).y;
    return float(sum);
  }();
  return integral;
}
}  // namespace

Vec3 cie1931_xyz(float l) {
  return {1.056f * lobe(l, 599.8f, 37.9f, 31.0f) + 0.362f * lobe(l, 442.0f, 16.0f, 26.7f) -
              0.065f * lobe(l, 501.1f, 20.4f, 26.2f),
          0.821f * lobe(l, 568.8f, 46.9f, 40.5f) + 0.286f * lobe(l, 530.9f, 16.3f, 31.1f),
          1.217f * lobe(l, 437.0f, 11.8f, 36.0f) + 0.681f * lobe(l, 459.0f, 26.0f, 13.8f)};
}

Vec3 xyz_to_linear_srgb(const Vec3& c) {
  return {3.240479f * c.x - 1.537150f * c.y - 0.498535f * c.z, -0.969256f * c.x + 1.875991f * c.y + 0.041556f * c.z,
          0.055648f * c.x - 0.204043f * c.y + 1.057311f * c.z};
}

Rgb spectrum_to_rgb(const std::vector<float>& wavelengths, const std::vector<float>& values, bool bounded) {
  glm::dvec3 xyz(0.0);
  for (int i = 0; i < kSteps; ++i) {
    const float w = kCieMin + float(i) / float(kSteps - 1) * (kCieMax - kCieMin);
    if (w < wavelengths.front() || w > wavelengths.back()) continue;
    const auto k = std::size_t(
        std::min<std::ptrdiff_t>(std::upper_bound(wavelengths.begin(), wavelengths.end(), w) - wavelengths.begin() - 1,
                                 std::ptrdiff_t(wavelengths.size()) - 2));
    const float t = (w - wavelengths[k]) / (wavelengths[k + 1] - wavelengths[k]);
    const float v = values[k] + t * (values[k + 1] - values[k]);
    xyz += glm::dvec3(cie1931_xyz(w)) * double(v);
  }
  Rgb rgb = xyz_to_linear_srgb(Vec3(xyz / double(y_integral())));
  rgb = glm::max(rgb, Rgb(0.0f));
  return bounded ? glm::min(rgb, Rgb(1.0f)) : rgb;
}

}  // namespace clr::scene
