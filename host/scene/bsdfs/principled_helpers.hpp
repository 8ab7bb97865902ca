#pragma once
// What Mitsuba 3's `principled` and `principledthin` share (its principledhelpers.h): the Schlick weight and Fresnel
// with Mitsuba's turn for light from the denser side, R0 of an IOR, and the map from roughness and anisotropy to
// the GGX alphas.
#include <algorithm>
#include <cmath>

#include "scene/frame.hpp"
#include "scene/microfacet.hpp"

namespace clr::scene {

// (1 − cos)^5, the Schlick weight.
inline float schlick_weight(float cos_theta) {
  const float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  return (m * m) * (m * m) * m;
}

// Schlick's Fresnel from R0 at the microfacet cosine cos_i, with Mitsuba's turn for light arriving from the denser
// side (the refracted cosine then drives the weight).
inline Rgb schlick(const Rgb& r0, float cos_i, float eta) {
  const float eta_it = cos_i >= 0 ? eta : 1.0f / eta, eta_ti = 1.0f / eta_it;
  float c = std::fabs(cos_i);
  if (!(eta_it > 1.0f)) c = std::sqrt(std::fmax(0.0f, 1.0f - (1.0f - cos_i * cos_i) * eta_ti * eta_ti));
  return r0 + (Rgb(1.0f) - r0) * schlick_weight(c);
}

inline float r0_of_eta(float eta) { return ((eta - 1.0f) / (eta + 1.0f)) * ((eta - 1.0f) / (eta + 1.0f)); }

// Burley's map of roughness and anisotropy to GGX alphas along the shading frame's x and y, floored at 0.001.
inline Microfacet principled_microfacet(float roughness, float anisotropic) {
  const float r2 = roughness * roughness;
  Microfacet mf;
  mf.type = Microfacet::Type::ggx;
  if (anisotropic != 0) {
    const float aspect = std::sqrt(1.0f - 0.9f * anisotropic);
    mf.alpha = std::fmax(0.001f, r2 / aspect);
    mf.alpha_v = std::fmax(0.001f, r2 * aspect);
  } else {
    mf.alpha = std::fmax(0.001f, r2);
  }
  return mf;
}

// The diffuse family of both plugins as f·cos θi, before their lobe weights: Burley's diffuse with retro-reflection
// (blended towards Hanrahan–Krueger's fake subsurface by `flatness`) times base_color/π, and the sheen (tinted
// towards base_color's hue by `sheen_tint`; Mitsuba gives it no 1/π). cos_view, cos_light > 0 (one side);
// cos_d = cos of the light direction to the half vector.
struct PrincipledDiffuse {
  Rgb diffuse, sheen;
};
inline PrincipledDiffuse principled_diffuse(const Rgb& base, const Rgb& tint, float roughness, float flatness,
                                            float sheen, float sheen_tint, float cos_view, float cos_light,
                                            float cos_d) {
  const float fo = schlick_weight(cos_light), fi = schlick_weight(cos_view);
  const float diffuse = (1.0f - 0.5f * fi) * (1.0f - 0.5f * fo);
  const float rr = 2.0f * roughness * cos_d * cos_d;
  float shape = diffuse + rr * (fo + fi + fo * fi * (rr - 1.0f));
  if (flatness != 0) {
    const float fss90 = 0.5f * rr;
    const float fss = (1.0f + fo * (fss90 - 1.0f)) * (1.0f + fi * (fss90 - 1.0f));
    const float subsurface = 1.25f * (fss * (1.0f / (cos_light + cos_view) - 0.5f) + 0.5f);
    shape += flatness * (subsurface - shape);
  }
  PrincipledDiffuse d{base * (cos_light * kInvPi * shape), Rgb(0.0f)};
  if (sheen > 0)
    d.sheen = (Rgb(1.0f) + sheen_tint * (tint - Rgb(1.0f))) * (sheen * schlick_weight(std::fabs(cos_d)) * cos_light);
  return d;
}

}  // namespace clr::scene
