#include "scene/pixel_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace clr::scene {
namespace {

constexpr double kPiD = 3.14159265358979323846;
// Midpoint-rule nodes over [-radius, radius] for ∫f, ∫|f| and max |f|: f is smooth (the tent's kink and the box's
// edges aside, which need no table), so the integrals come out within ~1e-7 and the maximum within its curvature
// over half a node's width, far inside the 1e-3 margin below. Every camera builds one: few nodes keep that cheap.
constexpr int kNodes = 1 << 12;
// Rejection rounds before giving up on a sample (then the pixel's centre): the rarest acceptance, the gaussian's
// 0.31, fails 256 rounds with probability below 1e-40.
constexpr int kMaxRounds = 256;

}  // namespace

PixelFilter::PixelFilter(Type type, float parameter, float b, float c)
    : type_(type), parameter_(parameter), b_(b), c_(c) {
  switch (type) {
    case Type::box:
    case Type::tent:
    case Type::lanczos:
      radius_ = parameter;
      break;
    case Type::gaussian:
      radius_ = 4 * parameter;
      break;
    case Type::mitchell:
    case Type::catmullrom:
      radius_ = 2;
      break;
  }
  double signed_sum = 0, abs_sum = 0, most = 0;
  for (int i = 0; i < kNodes; ++i) {
    const double f = eval(float(-double(radius_) + 2.0 * double(radius_) * (i + 0.5) / kNodes));
    signed_sum += f;
    abs_sum += std::fabs(f);
    most = std::max(most, std::fabs(f));
  }
  // 1 + 1e-3 over the sampled maximum: the true maximum between nodes is within the curvature's reach of it.
  max_abs_ = float(most * (1 + 1e-3));
  negative_scale_ = abs_sum > signed_sum ? float(abs_sum / signed_sum) : 1.0f;
}

float PixelFilter::negative_scale(float lo, float hi) const {
  if (negative_scale_ == 1.0f) return 1.0f;
  // Fewer nodes than the constructor's: this runs for each sample of an edge pixel (the filters are smooth
  // piecewise; 256 midpoints are within 1e-5 of the integrals).
  constexpr int kEdgeNodes = 256;
  double signed_sum = 0, abs_sum = 0;
  for (int i = 0; i < kEdgeNodes; ++i) {
    const double f = eval(float(double(lo) + double(hi - lo) * (i + 0.5) / kEdgeNodes));
    signed_sum += f;
    abs_sum += std::fabs(f);
  }
  return signed_sum > 0 && abs_sum > signed_sum ? float(abs_sum / signed_sum) : 1.0f;
}

float PixelFilter::eval(float xf) const {
  const double x = std::fabs(double(xf)), r = double(radius_);
  if (x > r) return 0.0f;
  switch (type_) {
    case Type::box:
      return 1.0f;
    case Type::tent:
      return float(1.0 - x / r);
    case Type::gaussian: {
      const double alpha = -1.0 / (2.0 * double(parameter_) * double(parameter_));
      return float(std::max(0.0, std::exp(alpha * x * x) - std::exp(alpha * r * r)));
    }
    case Type::mitchell:
    case Type::catmullrom: {
      const double t = 2.0 * x / r, t2 = t * t, t3 = t2 * t, B = b_, C = c_;
      if (t < 1) return float(((12 - 9 * B - 6 * C) * t3 + (-18 + 12 * B + 6 * C) * t2 + (6 - 2 * B)) / 6);
      return float(((-B - 6 * C) * t3 + (6 * B + 30 * C) * t2 + (-12 * B - 48 * C) * t + (8 * B + 24 * C)) / 6);
    }
    case Type::lanczos: {
      if (x < 1e-4) return 1.0f;
      const double px = kPiD * x;
      return float(std::sin(px) * std::sin(px / r) / (px * px / r));
    }
  }
  return 0.0f;
}

PixelFilter::Sample PixelFilter::sample(Pcg32& rng) const {
  if (type_ == Type::box) return {(rng.next_float() - 0.5f) * 2.0f * radius_, 1.0f};
  if (type_ == Type::tent) {
    // The tent's inverse CDF, each half apart.
    const float u = rng.next_float();
    const float x = u < 0.5f ? -1.0f + std::sqrt(2.0f * u) : 1.0f - std::sqrt(2.0f - 2.0f * u);
    return {x * radius_, 1.0f};
  }
  for (int round = 0; round < kMaxRounds; ++round) {
    const float x = (rng.next_float() - 0.5f) * 2.0f * radius_;
    const float f = eval(x);
    if (rng.next_float() * max_abs_ < std::fabs(f)) return {x, f < 0 ? -negative_scale_ : negative_scale_};
  }
  return {0.0f, 1.0f};
}

PixelFilter::Sample PixelFilter::sample(Pcg32& rng, float lo, float hi) const {
  lo = std::max(lo, -radius_);
  hi = std::min(hi, radius_);
  if (lo <= -radius_ && hi >= radius_) return sample(rng);
  // Cut by the film's edge: uniform positions over the part left, kept ∝ |f| (the box's at once). The pixel's
  // centre is inside the film, so at least half the support is left and the filter's peak with it.
  const float scale = negative_scale(lo, hi);
  for (int round = 0; round < kMaxRounds; ++round) {
    const float x = lo + rng.next_float() * (hi - lo);
    const float f = eval(x);
    if (rng.next_float() * max_abs_ < std::fabs(f)) return {x, f < 0 ? -scale : scale};
  }
  return {0.0f, 1.0f};
}

std::string PixelFilter::describe() const {
  char text[96];
  switch (type_) {
    case Type::box:
      std::snprintf(text, sizeof text, "box (radius %g)", double(radius_));
      break;
    case Type::tent:
      std::snprintf(text, sizeof text, "tent (radius %g)", double(radius_));
      break;
    case Type::gaussian:
      std::snprintf(text, sizeof text, "gaussian (stddev %g, radius %g)", double(parameter_), double(radius_));
      break;
    case Type::mitchell:
    case Type::catmullrom:
      std::snprintf(text, sizeof text, "%s (B %g, C %g)", type_ == Type::mitchell ? "mitchell" : "catmullrom",
                    double(b_), double(c_));
      break;
    case Type::lanczos:
      std::snprintf(text, sizeof text, "lanczos (%g lobes)", double(radius_));
      break;
  }
  return text;
}

}  // namespace clr::scene
