#pragma once
// Fresnel reflectance of smooth interfaces.
#include "scene/frame.hpp"

namespace clr::scene {

struct FresnelDielectric {
  float reflectance;  // F
  float cos_t;        // cosine of the refracted direction, signed opposite to cos_i (0 under total reflection)
  float eta_ti;       // IOR of the transmitted side over the incident side
};
// `eta` = IOR inside (below the surface, −z) over outside; cos_i signed (negative: incident from inside).
FresnelDielectric fresnel_dielectric(float cos_i, float eta);

// Conductor with complex IOR eta + i·k relative to the outside medium, per RGB channel (exact unpolarised formula).
Rgb fresnel_conductor(float cos_i, const Rgb& eta, const Rgb& k);

// Hemispherical average of F weighted by cosine (2∫F(μ)μ dμ), seen from the side where the relative IOR is `eta`.
// Integrated numerically so that it is exact for every eta rather than a fitted polynomial.
float diffuse_fresnel_reflectance(float eta);

// Direction refracted through the microfacet normal m (unit, same side as wi), given cos_t from fresnel_dielectric.
inline Vec3 refract(const Vec3& wi, const Vec3& m, float cos_i, float cos_t, float eta_ti) {
  return m * (cos_i / eta_ti + cos_t) - wi / eta_ti;
}

}  // namespace clr::scene
