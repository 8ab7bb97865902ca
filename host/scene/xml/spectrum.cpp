#include "scene/xml/spectrum.hpp"

#include <algorithm>
#include <cmath>

namespace clr::scene {
namespace {
constexpr int kSteps = 1000;

// ∫ȳ (or ∫ȳ·D65) over the integration grid, so that a flat spectrum of 1 has Y = 1 exactly.
float y_integral(bool d65) {
  const auto integrate = [](bool weighted) {
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) {
      const float w = kCieFirst + float(i) / float(kSteps - 1) * (kCieLast - kCieFirst);
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
// The CIE 1931 2° standard observer (x̄, ȳ, z̄), 360 to 830 nm every 5 nm (CIE 018:2019's table at those
// wavelengths), interpolated linearly between them. An analytic fit (Wyman, Sloan and Shirley 2013) stood here
// before: within 1 % of the peaks, it moved spectra's RGB by up to 0.5 % against Mitsuba 3, which reads this table.
constexpr float kCie1931[][3] = {
    {0.0001299f, 3.917e-06f, 0.0006061f},
    {0.0002321f, 6.965e-06f, 0.001086f},
    {0.0004149f, 1.239e-05f, 0.001946f},
    {0.0007416f, 2.202e-05f, 0.003486f},
    {0.001368f, 3.9e-05f, 0.00645f},
    {0.002236f, 6.4e-05f, 0.01055f},
    {0.004243f, 0.00012f, 0.02005f},
    {0.00765f, 0.000217f, 0.03621f},
    {0.01431f, 0.000396f, 0.06785f},
    {0.02319f, 0.00064f, 0.1102f},
    {0.04351f, 0.00121f, 0.2074f},
    {0.07763f, 0.00218f, 0.3713f},
    {0.13438f, 0.004f, 0.6456f},
    {0.21477f, 0.0073f, 1.03905f},
    {0.2839f, 0.0116f, 1.3856f},
    {0.3285f, 0.01684f, 1.62296f},
    {0.34828f, 0.023f, 1.74706f},
    {0.34806f, 0.0298f, 1.7826f},
    {0.3362f, 0.038f, 1.77211f},
    {0.3187f, 0.048f, 1.7441f},
    {0.2908f, 0.06f, 1.6692f},
    {0.2511f, 0.0739f, 1.5281f},
    {0.19536f, 0.09098f, 1.28764f},
    {0.1421f, 0.1126f, 1.0419f},
    {0.09564f, 0.13902f, 0.81295f},
    {0.05795f, 0.1693f, 0.6162f},
    {0.03201f, 0.20802f, 0.46518f},
    {0.0147f, 0.2586f, 0.3533f},
    {0.0049f, 0.323f, 0.272f},
    {0.0024f, 0.4073f, 0.2123f},
    {0.0093f, 0.503f, 0.1582f},
    {0.0291f, 0.6082f, 0.1117f},
    {0.06327f, 0.71f, 0.07825f},
    {0.1096f, 0.7932f, 0.05725f},
    {0.1655f, 0.862f, 0.04216f},
    {0.22575f, 0.91485f, 0.02984f},
    {0.2904f, 0.954f, 0.0203f},
    {0.3597f, 0.9803f, 0.0134f},
    {0.43345f, 0.99495f, 0.00875f},
    {0.51205f, 1.0f, 0.00575f},
    {0.5945f, 0.995f, 0.0039f},
    {0.6784f, 0.9786f, 0.00275f},
    {0.7621f, 0.952f, 0.0021f},
    {0.8425f, 0.9154f, 0.0018f},
    {0.9163f, 0.87f, 0.00165f},
    {0.9786f, 0.8163f, 0.0014f},
    {1.0263f, 0.757f, 0.0011f},
    {1.0567f, 0.6949f, 0.001f},
    {1.0622f, 0.631f, 0.0008f},
    {1.0456f, 0.5668f, 0.0006f},
    {1.0026f, 0.503f, 0.00034f},
    {0.9384f, 0.4412f, 0.00024f},
    {0.85445f, 0.381f, 0.00019f},
    {0.7514f, 0.321f, 0.0001f},
    {0.6424f, 0.265f, 5e-05f},
    {0.5419f, 0.217f, 3e-05f},
    {0.4479f, 0.175f, 2e-05f},
    {0.3608f, 0.1382f, 1e-05f},
    {0.2835f, 0.107f, 0.0f},
    {0.2187f, 0.0816f, 0.0f},
    {0.1649f, 0.061f, 0.0f},
    {0.1212f, 0.04458f, 0.0f},
    {0.0874f, 0.032f, 0.0f},
    {0.0636f, 0.0232f, 0.0f},
    {0.04677f, 0.017f, 0.0f},
    {0.0329f, 0.01192f, 0.0f},
    {0.0227f, 0.00821f, 0.0f},
    {0.01584f, 0.005723f, 0.0f},
    {0.0113592f, 0.004102f, 0.0f},
    {0.00811092f, 0.002929f, 0.0f},
    {0.00579035f, 0.002091f, 0.0f},
    {0.00410946f, 0.001484f, 0.0f},
    {0.00289933f, 0.001047f, 0.0f},
    {0.00204919f, 0.00074f, 0.0f},
    {0.00143997f, 0.00052f, 0.0f},
    {0.000999949f, 0.0003611f, 0.0f},
    {0.000690079f, 0.0002492f, 0.0f},
    {0.000476021f, 0.0001719f, 0.0f},
    {0.000332301f, 0.00012f, 0.0f},
    {0.000234826f, 8.48e-05f, 0.0f},
    {0.000166151f, 6e-05f, 0.0f},
    {0.000117413f, 4.24e-05f, 0.0f},
    {8.30753e-05f, 3e-05f, 0.0f},
    {5.87065e-05f, 2.12e-05f, 0.0f},
    {4.15099e-05f, 1.499e-05f, 0.0f},
    {2.93533e-05f, 1.06e-05f, 0.0f},
    {2.06738e-05f, 7.4657e-06f, 0.0f},
    {1.45598e-05f, 5.2578e-06f, 0.0f},
    {1.0254e-05f, 3.7029e-06f, 0.0f},
    {7.22146e-06f, 2.6078e-06f, 0.0f},
    {5.08587e-06f, 1.8366e-06f, 0.0f},
    {3.58165e-06f, 1.2934e-06f, 0.0f},
    {2.52253e-06f, 9.1093e-07f, 0.0f},
    {1.77651e-06f, 6.4153e-07f, 0.0f},
    {1.25114e-06f, 4.5181e-07f, 0.0f},
};

}  // namespace

float cie_d65(float lambda) {
  const float x = (lambda - 360.0f) / 10.0f;
  constexpr int n = int(sizeof(kD65) / sizeof(kD65[0]));
  if (!(x >= 0.0f && x <= float(n - 1))) return 0.0f;
  const int i = std::min(int(x), n - 2);
  const float f = x - float(i);
  return kD65[i] * (1.0f - f) + kD65[i + 1] * f;
}

Vec3 cie1931_xyz(float lambda) {
  const float x = (lambda - kCieFirst) / 5.0f;
  constexpr int n = int(sizeof(kCie1931) / sizeof(kCie1931[0]));
  if (!(x >= 0.0f && x <= float(n - 1))) return Vec3(0.0f);
  const int i = std::min(int(x), n - 2);
  const float f = x - float(i);
  return Vec3(kCie1931[i][0], kCie1931[i][1], kCie1931[i][2]) * (1.0f - f) +
         Vec3(kCie1931[i + 1][0], kCie1931[i + 1][1], kCie1931[i + 1][2]) * f;
}

Vec3 xyz_to_linear_srgb(const Vec3& c) {
  return {3.240479f * c.x - 1.537150f * c.y - 0.498535f * c.z, -0.969256f * c.x + 1.875991f * c.y + 0.041556f * c.z,
          0.055648f * c.x - 0.204043f * c.y + 1.057311f * c.z};
}

Rgb spectrum_to_rgb(const std::vector<float>& wavelengths, const std::vector<float>& values, bool bounded, bool d65) {
  glm::dvec3 xyz(0.0);
  for (int i = 0; i < kSteps; ++i) {
    const float w = kCieFirst + float(i) / float(kSteps - 1) * (kCieLast - kCieFirst);
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
