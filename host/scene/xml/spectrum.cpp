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

// ∫ȳ (or ∫ȳ·D65) over the integration grid, so that a flat spectrum of 1 has Y = 1 exactly.
float y_integral(bool d65) {
  const auto integrate = [](bool weighted) {
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) {
      const float w = kCieMin + float(i) / float(kSteps - 1) * (kCieMax - kCieMin);
      sum += double(cie1931_xyz(w).y) * (weighted ? double(cie_d65(w)) : 1.0);
    }
    return float(sum);
  };
  static const float plain = integrate(false), weighted = integrate(true);
  return d65 ? weighted : plain;
}

// CIE standard illuminant D65, 360 to 830 nm every 10 nm (CIE 15:2004, table T.1).
constexpr float kD65[] = {46.6383f, 52.0891f, 49.9755f, 54.6482f, 82.7549f, 91.486f,  93.4318f, 86.6823f,
                          104.865f, 117.008f, 117.812f, 114.861f, 115.923f, 108.811f, 109.354f, 107.802f,
                          104.79f,  107.689f, 104.405f, 104.046f, 100.0f,   96.3342f, 95.788f,  88.6856f,
                          90.0062f, 89.5991f, 87.6987f, 83.2886f, 83.6992f, 80.0268f, 80.2146f, 82.2778f,
                          78.2842f, 69.7213f, 71.6091f, 74.349f,  61.604f,  69.8856f, 75.087f,  63.5927f,
                          46.4182f, 66.8054f, 63.3828f, 64.304f,  59.4519f, 51.959f,  57.4406f, 60.3125f};
}  // namespace

float cie_d65(float lambda) {
  const float x = (lambda - 360.0f) / 10.0f;
  constexpr int n = int(sizeof(kD65) / sizeof(kD65[0]));
  if (!(x >= 0.0f && x <= float(n - 1))) return 0.0f;
  const int i = std::min(int(x), n - 2);
  const float f = x - float(i);
  return kD65[i] * (1.0f - f) + kD65[i + 1] * f;
}

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

Rgb spectrum_to_rgb(const std::vector<float>& wavelengths, const std::vector<float>& values, bool bounded, bool d65) {
  glm::dvec3 xyz(0.0);
  for (int i = 0; i < kSteps; ++i) {
    const float w = kCieMin + float(i) / float(kSteps - 1) * (kCieMax - kCieMin);
    if (w < wavelengths.front() || w > wavelengths.back()) continue;
    const auto k = std::size_t(
        std::min<std::ptrdiff_t>(std::upper_bound(wavelengths.begin(), wavelengths.end(), w) - wavelengths.begin() - 1,
                                 std::ptrdiff_t(wavelengths.size()) - 2));
    const float t = (w - wavelengths[k]) / (wavelengths[k + 1] - wavelengths[k]);
    const float v = values[k] + t * (values[k + 1] - values[k]);
    xyz += glm::dvec3(cie1931_xyz(w)) * double(v) * (d65 ? double(cie_d65(w)) : 1.0);
  }
  Rgb rgb = xyz_to_linear_srgb(Vec3(xyz / double(y_integral(d65))));
  rgb = glm::max(rgb, Rgb(0.0f));
  return bounded ? glm::min(rgb, Rgb(1.0f)) : rgb;
}

}  // namespace clr::scene
