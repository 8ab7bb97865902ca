// The sRGB transfer function (IEC 61966-2-1) both ways: for 8- and 16-bit images and for Mitsuba's <srgb> colours.
#pragma once

#include <cmath>

namespace clr::image {

inline float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
inline float linear_to_srgb(float c) {
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace clr::image
