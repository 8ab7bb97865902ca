#include "scene/sunsky.hpp"

#include <algorithm>
#include <cmath>

#include "scene/sky/hosek_wilkie_data.inc"
#include "scene/xml/spectrum.hpp"

namespace clr::scene {
namespace {

namespace hw = hosek_wilkie;

// Mitsuba's RGB sunsky divides the model's output by the CIE Y normalisation of its spectra (MI_CIE_Y_NORMALIZATION)
// and scales the sun by a constant its authors left unexplained; both measured off Mitsuba 3.9.1 (docs/scenes.md).
constexpr double kCieYNormalization = 1.0 / 106.7502593994140625;
constexpr double kSunRgbConversion = 467.069280386;
// The solar radius the solar radiance data were fitted for (and Mitsuba's default aperture is twice), and its disc's
// solid angle.
constexpr double kSolarRadius = M_PI * (0.5 * 0.5358) / 180.0;
const double kSolarSolidAngle = 2 * M_PI * (1 - std::cos(kSolarRadius));

// The quintic Bézier over the six control points (stride apart) at x, as the model interpolates elevation.
double bezier(const double* points, int stride, double x) {
  constexpr double kBinomial[6] = {1, 5, 10, 10, 5, 1};
  double sum = 0;
  for (int k = 0; k < 6; ++k) sum += kBinomial[k] * std::pow(x, k) * std::pow(1 - x, 5 - k) * points[k * stride];
  return sum;
}

// A dataset's value at (turbidity, albedo, elevation parameter x): linear in turbidity and albedo, Bézier in x. Each
// (albedo, turbidity) entry holds six control points of `stride` values; `offset` picks the value within them.
double cook(const double* data, int stride, double turbidity, double albedo, double x, int offset) {
  const int low = std::clamp(int(turbidity), 1, 10);
  const double frac = turbidity - low;
  const int block = 6 * stride;
  auto at = [&](int a, int t) { return bezier(data + (a * 10 + (t - 1)) * block + offset, stride, x); };
  double v = (1 - albedo) * (1 - frac) * at(0, low) + albedo * (1 - frac) * at(1, low);
  if (low < 10) v += (1 - albedo) * frac * at(0, low + 1) + albedo * frac * at(1, low + 1);
  return v;
}

// Solar radiance at wavelength index w (320 + 40w nm) seen at elevation `el` (radians), between the two turbidities.
double solar(int w, double turbidity, double el) {
  int low = int(turbidity) - 1;
  double frac = turbidity - (low + 1);
  if (low == 9) {
    low = 8;
    frac = 1;
  }
  el = std::max(el, 0.0);
  const int pos = std::min(int(std::cbrt(2 * el / M_PI) * 45), 44);
  const double x = el - std::pow(pos / 45.0, 3) * (M_PI / 2);
  auto segment = [&](int t) {
    const double* c = &hw::kSolar[w][(t * 45 + pos) * 4];  // x³ first
    return ((c[0] * x + c[1]) * x + c[2]) * x + c[3];
  };
  return (1 - frac) * segment(low) + frac * segment(low + 1);
}

double limb_darkening(int w, double cos_psi) {
  const double* c = hw::kLimbDarkening[w];
  return c[0] + cos_psi * (c[1] + cos_psi * (c[2] + cos_psi * (c[3] + cos_psi * (c[4] + cos_psi * c[5]))));
}

// The colour-matching functions in linear sRGB at the data's wavelengths, averaged as Mitsuba averages its 11 samples.
Vec3 rgb_weight(int w) { return xyz_to_linear_srgb(cie1931_xyz(320.0f + 40.0f * float(w))) / 11.0f; }

// The limb-darkened disc's radiance in RGB at view elevation `el` and cos ψ (ψ the angle across the disc from its
// centre, ψ = π/2 at its rim), before the aperture's area ratio and Mitsuba's scale.
Rgb complex_sun_rgb(double turbidity, double el, double cos_psi) {
  glm::dvec3 sum(0.0);
  for (int w = 0; w < 11; ++w) sum += glm::dvec3(rgb_weight(w)) * solar(w, turbidity, el) * limb_darkening(w, cos_psi);
  return Rgb(sum);
}

double elevation(const Vec3& d) { return std::asin(std::clamp(double(d.z), -1.0, 1.0)); }

}  // namespace

SunSky::SunSky(const SunSkyParameters& p) : p_(p) {
  const double eta = elevation(p.sun);
  up_ = eta >= 0;
  radius_ = double(p.sun_aperture_deg) * M_PI / 360.0;
  // Mitsuba's scale of the sun, and the ratio of the fitted disc's solid angle to this one's, so that another
  // aperture keeps the power.
  sun_factor_ = kSunRgbConversion * kCieYNormalization * double(p.sun_scale) * kSolarSolidAngle / sun_solid_angle();
  if (!up_) return;
  const double x = std::min(std::cbrt(2 * eta / M_PI), 1 - 1e-7);
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < 9; ++i) config_[c][i] = cook(hw::kSkyRgb[c], 9, p.turbidity, p.albedo[c], x, i);
    radiance_[c] = cook(hw::kSkyRgbRadiance[c], 1, p.turbidity, p.albedo[c], x, 0);
  }
  // The flat disc carries the limb-darkened disc's power: its radiance integrated over the fitted solar radius
  // (Gauss–Legendre in the angle from the centre, midpoints around it), over that solid angle.
  constexpr int kRadial = 32, kAround = 64;
  constexpr double kNodes[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                                0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
  constexpr double kWeights[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066553286141, 0.3626837833783620,
                                  0.3626837833783620, 0.3137066553286141, 0.2223810344533745, 0.1012285362903763};
  const Frame frame(p.sun);
  glm::dvec3 integral(0.0);
  for (int r = 0; r < kRadial; ++r)
    for (int k = 0; k < 8; ++k) {
      // γ in [r, r+1]·R/kRadial: Gauss–Legendre per ring, which the disc's edge (cos ψ → 0, a square root) needs.
      const double gamma = (r + 0.5 + 0.5 * kNodes[k]) * kSolarRadius / kRadial;
      const double w_gamma = 0.5 * kWeights[k] * kSolarRadius / kRadial * std::sin(gamma);
      const double cos_psi = std::sqrt(std::max(0.0, 1 - std::pow(std::sin(gamma) / std::sin(kSolarRadius), 2)));
      for (int a = 0; a < kAround; ++a) {
        const double phi = 2 * M_PI * (a + 0.5) / kAround;
        const Vec3 d = frame.to_world(Vec3(float(std::sin(gamma) * std::cos(phi)),
                                           float(std::sin(gamma) * std::sin(phi)), float(std::cos(gamma))));
        integral += glm::dvec3(complex_sun_rgb(p.turbidity, elevation(d), cos_psi)) * w_gamma * (2 * M_PI / kAround);
      }
    }
  flat_sun_ = Rgb(integral / kSolarSolidAngle * sun_factor_);
}

Rgb SunSky::sky(const Vec3& d) const {
  if (!up_ || d.z < 0 || p_.sky_scale == 0) return Rgb(0.0f);
  const double cos_theta = d.z, cos_gamma = std::clamp(double(glm::dot(d, p_.sun)), -1.0, 1.0);
  const double gamma = std::acos(cos_gamma);
  Rgb out;
  for (int c = 0; c < 3; ++c) {
    const double* k = config_[c];
    const double mie = (1 + cos_gamma * cos_gamma) / std::pow(1 + k[8] * k[8] - 2 * k[8] * cos_gamma, 1.5);
    const double f = (1 + k[0] * std::exp(k[1] / (cos_theta + 0.01))) *
                     (k[2] + k[3] * std::exp(k[4] * gamma) + k[5] * cos_gamma * cos_gamma + k[6] * mie +
                      k[7] * std::sqrt(cos_theta));
    out[c] = float(f * radiance_[c] * kCieYNormalization * double(p_.sky_scale));
  }
  return out;
}

double SunSky::sun_solid_angle() const { return 4 * M_PI * std::pow(std::sin(0.5 * radius_), 2); }  // 2π(1 − cos r)

bool SunSky::in_sun(const Vec3& d) const {
  const glm::dvec3 c = glm::cross(glm::dvec3(d), glm::dvec3(p_.sun));
  return glm::dot(d, p_.sun) > 0 &&
         glm::dot(c, c) <= std::pow(std::sin(radius_), 2) * glm::dot(glm::dvec3(d), glm::dvec3(d));
}

Vec3 SunSky::sample_sun(const Vec2& u) const {
  const double one_minus_cos = double(u.x) * sun_solid_angle() / (2 * M_PI);
  const double sin_t = std::sqrt(std::max(0.0, one_minus_cos * (2 - one_minus_cos))), phi = 2 * M_PI * double(u.y);
  return Frame(p_.sun).to_world(
      Vec3(float(sin_t * std::cos(phi)), float(sin_t * std::sin(phi)), float(1 - one_minus_cos)));
}

Rgb SunSky::limb_darkened_sun(const Vec3& d) const {
  const glm::dvec3 c = glm::cross(glm::dvec3(glm::normalize(d)), glm::dvec3(p_.sun));
  const double cos_psi = std::sqrt(std::max(0.0, 1 - glm::dot(c, c) / std::pow(std::sin(radius_), 2)));
  return complex_sun_rgb(p_.turbidity, elevation(d), cos_psi) * float(sun_factor_);
}

Rgb SunSky::sun(const Vec3& d) const {
  if (!up_ || d.z < 0 || !in_sun(d)) return Rgb(0.0f);
  return p_.complex_sun ? limb_darkened_sun(d) : flat_sun_;
}

Vec3 sun_direction(double latitude, double longitude, double timezone, int year, int month, int day, double hour,
                   double minute, double second) {
  // Universal time and the days since 2000-01-01 12:00 UT (the Julian day by Fliegel and Van Flandern's integer
  // formula, C's truncating division).
  const double ut = hour - timezone + (minute + second / 60.0) / 60.0;
  const int a1 = (month - 14) / 12;
  const long a2 = (1461L * (year + 4800 + a1)) / 4 + (367L * (month - 2 - 12 * a1)) / 12 -
                  (3L * ((year + 4900 + a1) / 100)) / 4 + day - 32075;
  const double n = double(a2) - 0.5 + ut / 24.0 - 2451545.0;
  // Ecliptic coordinates.
  const double omega = 2.1429 - 0.0010394594 * n, l = 4.8950630 + 0.017202791698 * n, g = 6.2400600 + 0.0172019699 * n;
  const double lambda =
      l + 0.03341607 * std::sin(g) + 0.00034894 * std::sin(2 * g) - 0.0001134 - 0.0000203 * std::sin(omega);
  const double epsilon = 0.4090928 - 6.2140e-9 * n + 0.0000396 * std::cos(omega);
  // Celestial coordinates.
  double ra = std::atan2(std::cos(epsilon) * std::sin(lambda), std::cos(lambda));
  if (ra < 0) ra += 2 * M_PI;
  const double declination = std::asin(std::sin(epsilon) * std::sin(lambda));
  // Local coordinates: zenith angle and azimuth (from north towards east), then parallax.
  const double gmst = 6.6974243242 + 0.0657098283 * n + ut;
  const double lmst = (gmst * 15 + longitude) * M_PI / 180, hour_angle = lmst - ra;
  const double lat = latitude * M_PI / 180;
  double zenith =
      std::acos(std::cos(lat) * std::cos(hour_angle) * std::cos(declination) + std::sin(declination) * std::sin(lat));
  double azimuth =
      std::atan2(-std::sin(hour_angle), std::tan(declination) * std::cos(lat) - std::sin(lat) * std::cos(hour_angle));
  if (azimuth < 0) azimuth += 2 * M_PI;
  zenith += (6371.01 / 149597890.0) * std::sin(zenith);
  // Mitsuba's frame: φ = azimuth − π from +x.
  const double phi = azimuth - M_PI;
  return {float(std::sin(zenith) * std::cos(phi)), float(std::sin(zenith) * std::sin(phi)), float(std::cos(zenith))};
}

}  // namespace clr::scene
