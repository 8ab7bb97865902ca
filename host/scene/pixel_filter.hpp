#pragma once
// The film's reconstruction filter (Mitsuba's <rfilter>): box, tent, gaussian, mitchell, catmullrom and lanczos with
// Mitsuba 3's parameters and defaults; a film that names none gets Mitsuba's default, the gaussian. Separable, as
// Mitsuba's: f(x, y) = f(x) f(y), x and y in pixels from the pixel's centre.
//
// Mitsuba splats every sample into the pixels its filter covers and divides each pixel by its sum of weights. We draw
// each pixel's sample positions from the filter instead (filter importance sampling): the same converged image,
// ∫ f L / ∫ f over the filter's support, while every pixel keeps samples of its own, so an image does not depend on
// how passes, resumes, chunks or MPI ranks split it. Positions are drawn exactly ∝ |f| (the box and the tent by
// inversion, the others by rejection), so a sample's weight is 1 for filters without negative lobes, which keeps a
// constant image constant, and ±∫|f| / ∫f for those with them (mitchell, catmullrom, lanczos).
#include <string>

#include "common/pcg32.hpp"

namespace clr::scene {

class PixelFilter {
 public:
  enum class Type { box, tent, gaussian, mitchell, catmullrom, lanczos };

  // Mitsuba's defaults: box radius 0.5, tent radius 1, gaussian stddev 0.5 (radius 4 stddev), mitchell and
  // catmullrom B and C (1/3, 1/3 and 0, 0.5) with radius 2, lanczos 3 lobes (radius = lobes).
  PixelFilter() : PixelFilter(Type::gaussian, 0.5f) {}
  // `parameter`: the box's and tent's radius, the gaussian's stddev, lanczos' lobes; mitchell and catmullrom take
  // B and C. The caller checks ranges (the loader: positive and finite).
  PixelFilter(Type type, float parameter, float b = 1.0f / 3.0f, float c = 1.0f / 3.0f);

  Type type() const { return type_; }
  float radius() const { return radius_; }
  float eval(float x) const;  // Mitsuba's f(x), not normalised
  std::string describe() const;

  struct Sample {
    float offset;  // from the pixel's centre, in pixels
    float weight;
  };
  // One axis' offset: one number from `rng` for the box and the tent, a few on average for the others.
  Sample sample(Pcg32& rng) const;
  // The same with the offset kept within [lo, hi]: where the film's edge cuts the filter. Mitsuba draws samples
  // only inside the film, so a pixel at its edge converges to ∫ f L / ∫ f over the part of the filter inside the
  // film; drawing ∝ |f| over that part, with weights ±∫|f| / ∫f of it, converges to the same.
  Sample sample(Pcg32& rng, float lo, float hi) const;

 private:
  Type type_;
  float radius_, parameter_, b_, c_;
  float negative_scale(float lo, float hi) const;  // ∫|f| / ∫f over [lo, hi]: 1 without negative lobes

  float max_abs_ = 1;         // max |f|: the rejection's bound
  float negative_scale_ = 1;  // ∫|f| / ∫f, the weight's magnitude
};

}  // namespace clr::scene
