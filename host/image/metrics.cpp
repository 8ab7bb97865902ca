#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "image/image.hpp"

namespace clr::image {
namespace {
std::string size_text(const Image& img) { return std::to_string(img.width) + "x" + std::to_string(img.height); }
}  // namespace

Image box_downsample(const Image& img, int f) {
  if (f < 1 || img.width % f || img.height % f)
    throw InputError("cannot box-downsample " + size_text(img) + " by " + std::to_string(f));
  Image out(img.width / f, img.height / f);
  const float norm = 1.0f / float(f * f);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      double sum[3] = {0, 0, 0};
      for (int dy = 0; dy < f; ++dy)
        for (int dx = 0; dx < f; ++dx) {
          const float* p = img.pixel(x * f + dx, y * f + dy);
          for (int c = 0; c < 3; ++c) sum[c] += p[c];
        }
      for (int c = 0; c < 3; ++c) out.pixel(x, y)[c] = float(sum[c]) * norm;
    }
  return out;
}

void require_matching_size(int ref_width, int ref_height, int width, int height) {
  if (ref_width == width && ref_height == height) return;
  if (width > 0 && height > 0 && ref_width % width == 0 && ref_height % height == 0 &&
      ref_width / width == ref_height / height)
    return;
  throw InputError("reference is " + std::to_string(ref_width) + "x" + std::to_string(ref_height) + ", image is " +
                   std::to_string(width) + "x" + std::to_string(height) +
                   ": sizes must be equal or the reference an integer multiple of the image");
}

Image match_size(const Image& ref, const Image& like) {
  require_matching_size(ref.width, ref.height, like.width, like.height);
  if (ref.width == like.width && ref.height == like.height) return ref;
  return box_downsample(ref, ref.width / like.width);
}

void require_usable_reference(const Image& ref, const std::string& what) {
  if (std::none_of(ref.rgb.begin(), ref.rgb.end(), [](float v) { return std::isfinite(v); }))
    throw InputError(what + ": it holds no finite value (all NaN or infinite): nothing to measure against");
}

Metrics compare(const Image& a, const Image& ref) {
  if (a.width != ref.width || a.height != ref.height)
    throw InputError("cannot compare " + size_text(a) + " with " + size_text(ref));
  require_usable_reference(ref, "the reference");
  Metrics m;
  double mape = 0, mse = 0, relmse = 0, sum = 0, ref_sum = 0;
  std::size_t used = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const double x = a.rgb[i], r = ref.rgb[i];
    if (!std::isfinite(x)) ++m.non_finite;
    if (!std::isfinite(r)) ++m.reference_non_finite;
    if (!std::isfinite(x) || !std::isfinite(r)) continue;
    ++used;
    const double d = x - r;
    mape += std::abs(d) / (std::abs(r) + 0.01);
    mse += d * d;
    relmse += d * d / (r * r + 0.01);
    sum += x;
    ref_sum += r;
  }
  if (m.non_finite > 0 || used == 0) {
    m.mape = m.mse = m.relmse = m.mean_ratio = std::numeric_limits<double>::quiet_NaN();
  } else {
    m.mape = mape / double(used);
    m.mse = mse / double(used);
    m.relmse = relmse / double(used);
    m.mean_ratio = ref_sum > 0 ? sum / ref_sum : std::numeric_limits<double>::quiet_NaN();
  }
  return m;
}

std::string describe(const Metrics& m) {
  char text[200];
  std::snprintf(text, sizeof text, "MAPE %.6g  MSE %.6g  relMSE %.6g  mean ratio %.4g", m.mape, m.mse, m.relmse,
                m.mean_ratio);
  std::string s = text;
  if (m.non_finite) s += "  (" + std::to_string(m.non_finite) + " non-finite values in the image: metrics undefined)";
  if (m.reference_non_finite)
    s += "  (" + std::to_string(m.reference_non_finite) + " non-finite values in the reference, left out)";
  return s;
}

Image error_map(const Image& a, const Image& ref, float max_error) {
  if (a.width != ref.width || a.height != ref.height)
    throw InputError("cannot compare " + size_text(a) + " with " + size_text(ref));
  Image out(a.width, a.height);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      float e = 0;
      for (int c = 0; c < 3; ++c)
        e += std::abs(a.pixel(x, y)[c] - ref.pixel(x, y)[c]) / (std::abs(ref.pixel(x, y)[c]) + 0.01f);
      // Non-finite pixels show as the maximum error: they are the worst kind.
      const float t = std::isfinite(e) ? std::clamp(e / 3.0f / max_error, 0.0f, 1.0f) : 1.0f;
      // Blue → cyan → green → yellow → red, piecewise linear in four equal segments.
      const float r = std::clamp(4.0f * t - 2.0f, 0.0f, 1.0f);
      const float g = t < 0.75f ? std::clamp(4.0f * t, 0.0f, 1.0f) : std::clamp(4.0f - 4.0f * t, 0.0f, 1.0f);
      const float b = std::clamp(2.0f - 4.0f * t, 0.0f, 1.0f);
      float* p = out.pixel(x, y);
      p[0] = r;
      p[1] = g;
      p[2] = b;
    }
  return out;
}

}  // namespace clr::image
