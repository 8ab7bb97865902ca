#pragma once
// Mitsuba 3's `sunsky` emitter as its RGB variants compute it: the Hosek–Wilkie sky dome (2012) and solar disc (2013)
// from the authors' data (sky/hosek_wilkie_data.inc, BSD-3), in the emitter's local frame, z up (Mitsuba's: +x south,
// +y west). Directions below the horizon are black, and so is everything while the sun is below it, as in Mitsuba.
#include "scene/frame.hpp"

namespace clr::scene {

struct SunSkyParameters {
  Vec3 sun{0, 0, 1};    // unit, local: towards the sun's centre
  float turbidity = 3;  // [1, 10]
  Rgb albedo{0.3f};     // ground albedo per channel, [0, 1]
  float sun_scale = 1, sky_scale = 1;
  float sun_aperture_deg = 0.5358f;  // the disc's full angle
  bool complex_sun = false;          // limb-darkened, elevation-dependent disc instead of a flat one of equal power
};

class SunSky {
 public:
  explicit SunSky(const SunSkyParameters& p);

  // Radiance from local direction `d` (unit, pointing away from the scene).
  Rgb sky(const Vec3& d) const;
  Rgb sun(const Vec3& d) const;
  const SunSkyParameters& parameters() const { return p_; }
  // The sun's disc: whether `d` lies in it (by sin²γ from a cross product: 1 − cos γ is ~1e-5 there, below what a
  // float cosine resolves), its solid angle, and a direction uniform in it from two uniforms.
  bool in_sun(const Vec3& d) const;
  double sun_solid_angle() const;
  Vec3 sample_sun(const Vec2& u) const;
  // The flat disc's radiance (the complex disc's mean): what the sun's share of sampling is weighed by.
  Rgb sun_radiance() const { return flat_sun_; }

 private:
  Rgb limb_darkened_sun(const Vec3& d) const;

  SunSkyParameters p_;
  bool up_ = false;  // the sun above the horizon
  double config_[3][9] = {};
  double radiance_[3] = {};
  double radius_ = 0;      // the disc's angular radius
  double sun_factor_ = 0;  // from the model's solar radiance to this disc's RGB radiance
  Rgb flat_sun_{0.0f};
};

// Where the sun stands in the emitter's local frame at a place and local time (latitude and longitude in degrees,
// east positive; timezone in hours east of UTC): the PSA algorithm (Blanco-Muriel et al. 2001, "Computing the solar
// vector"), with parallax and without refraction, as Mitsuba computes it (in double where Mitsuba's Julian day is in
// float: up to 0.02° apart).
Vec3 sun_direction(double latitude, double longitude, double timezone, int year, int month, int day, double hour,
                   double minute, double second);

}  // namespace clr::scene
