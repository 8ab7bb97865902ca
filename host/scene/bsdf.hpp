#pragma once
// Scattering at a surface point, in the local shading frame (z = shading normal), the interface both the reference
// path tracer and the Neural Radiosity trainer use. Directions point away from the surface: `wo` towards the
// viewer (the previous path vertex), `wi` towards the light. Texture lookups take the surface point `at` (its uv,
// and for mesh attributes its triangle and barycentrics).
//
// eval returns f(wo, wi)·|cos θi| of the non-delta lobes; pdf the solid-angle density with which sample() draws wi
// (lobe-selection probability included); sample() returns the throughput weight f·|cos θi|/pdf. Delta lobes
// (mirrors, smooth glass) never appear in eval/pdf; sample() flags them with `delta` and their pdf is the discrete
// probability of choosing them.
#include <cmath>
#include <memory>
#include <optional>

#include "scene/frame.hpp"
#include "scene/texture.hpp"

namespace clr::scene {

struct BsdfSample {
  Vec3 wi;
  Rgb weight;  // f·|cos θi| / pdf
  float pdf;   // solid angle (non-delta) or the lobe's discrete probability (delta)
  bool delta;
};

// Mitsuba's `bumpmap`: a height field whose uv gradient tilts the shading normal.
struct BumpMap {
  Texture height;
  float scale = 1.0f;
};

class Bsdf {
 public:
  virtual ~Bsdf() = default;
  virtual Rgb eval(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const = 0;
  virtual float pdf(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const = 0;
  // `u_lobe` chooses among lobes (reflect/refract, specular/diffuse), `u` draws the direction. nullopt: absorbed.
  virtual std::optional<BsdfSample> sample(const TexturePoint& at, const Vec3& wo, float u_lobe,
                                           const Vec2& u) const = 0;
  // What a network sees as the surface colour: the reflectance a unit white light would produce at normal
  // incidence (diffuse albedo, conductor F0 tint, plastic substrate).
  virtual Rgb albedo(const TexturePoint& at) const = 0;
  // 1 for Lambertian, the microfacet alpha for glossy lobes, 0 for purely specular.
  virtual float roughness() const = 0;
  // False for purely specular materials: no light sampling there, no training points (docs/design.md §2).
  virtual bool has_non_delta() const = 0;
  // False when the surface is black seen from below its shading normal (wo.z ≤ 0), as Mitsuba's reflective
  // BSDFs are; true for twosided wrappers and dielectrics. Radiance leaving a black side is exactly zero, so the
  // trainer neither trains nor queries the network there.
  virtual bool two_sided() const { return false; }
  // Geometry-level wrappers (Mitsuba's mask and bumpmap) expose their textures; wrappers of wrappers forward.
  virtual const Texture* opacity() const { return nullptr; }
  virtual const BumpMap* bump() const { return nullptr; }
  // Mitsuba's `normalmap`: the shading normal in the tangent frame (dp/du, n × dp/du, n), as raw RGB in [0, 1].
  virtual const Texture* normal_map() const { return nullptr; }
  // An anisotropic lobe, oriented along dp/du like Mitsuba's (so the shading frame must follow the uv map).
  virtual bool anisotropic() const { return false; }

 protected:
  // A continuous sample at `wi` drawn with this BSDF's own density (pdf() over all its lobes, as multi-lobe BSDFs
  // sample: one lobe picked, the density the mixture's): weight f·cos / p; nullopt where the density vanishes.
  std::optional<BsdfSample> continuous_sample(const TexturePoint& at, const Vec3& wo, const Vec3& wi) const {
    const float p = pdf(at, wo, wi);
    if (!(p > 0)) return std::nullopt;
    return BsdfSample{wi, eval(at, wo, wi) / p, p, false};
  }
};

// Evaluation of a BSDF at a world-space point: the frame it was hit with plus where its textures are looked up. The
// trainer's view.
struct BsdfPoint {
  const Bsdf* bsdf;
  Frame frame;
  TexturePoint at;
  // Where a bump or normal map tilted `frame`, the shading normal before it (else zero). Mitsuba 3.9's bumpmap and
  // normalmap treat a tilted frame in three ways, all on by default there and all needed here: a bump-mapped
  // principled glass rendered 14 %, then 1.2 % brighter than in Mitsuba without them (docs/scenes.md):
  //  - the viewer `wo` sees the tilted normal from the side it sees the untilted one: where it would not, the tilt is
  //    mirrored about the untilted normal (flip_invalid_normals), so that a glass is not entered from inside;
  //  - the BSDF is zero for an incident direction on one side of the tilted normal and the other side of the
  //    untilted one: a tilted frame would otherwise pass light through an opaque surface, or reflect what a glass
  //    surface transmits;
  //  - f and the sample weight are scaled by the microfacet shadowing of Estevez et al. 2019
  //    (use_shadowing_function), which darkens grazing incident directions more the more the normal is tilted.
  Vec3 untilted_normal{0.0f};

  Rgb eval(const Vec3& wo_world, const Vec3& wi_world) const {
    const Frame f = frame_seen_from(wo_world);
    if (!same_side(f, wi_world)) return Rgb(0.0f);
    return bsdf->eval(at, f.to_local(wo_world), f.to_local(wi_world)) * shadowing(f, wi_world);
  }
  float pdf(const Vec3& wo_world, const Vec3& wi_world) const {
    const Frame f = frame_seen_from(wo_world);
    if (!same_side(f, wi_world)) return 0.0f;
    return bsdf->pdf(at, f.to_local(wo_world), f.to_local(wi_world));
  }
  // wi in the result is in world space.
  std::optional<BsdfSample> sample(const Vec3& wo_world, float u_lobe, const Vec2& u) const {
    const Frame f = frame_seen_from(wo_world);
    auto s = bsdf->sample(at, f.to_local(wo_world), u_lobe, u);
    if (!s) return s;
    s->wi = f.to_world(s->wi);
    if (!same_side(f, s->wi)) return std::nullopt;
    s->weight *= shadowing(f, s->wi);
    return s;
  }

  // Whether a viewer at `wo_world` sees the side that scatters: any side of a two-sided BSDF, else the side above
  // the normal before a tilt (a viewer there sees the tilt mirrored to its side: frame_seen_from), or above the
  // shading normal where nothing tilted it.
  bool seen_from_scattering_side(const Vec3& wo_world) const {
    const Vec3& n = untilted_normal != Vec3(0.0f) ? untilted_normal : frame.n;
    return bsdf->two_sided() || glm::dot(wo_world, n) > 0.0f;
  }
  // The frame the BSDF is evaluated in for a viewer at `wo_world`: `frame`, or where the viewer is on one side of
  // the tilted normal and the other side (or in the plane) of the untilted one, `frame` with its tilt mirrored about
  // the untilted normal (Mitsuba negates the tilted normal's tangential part in the untilted frame: n' = 2(n·u)u − n).
  Frame frame_seen_from(const Vec3& wo_world) const {
    const Vec3& u = untilted_normal;
    if (u == Vec3(0.0f) || glm::dot(wo_world, u) * glm::dot(wo_world, frame.n) > 0.0f) return frame;
    Frame f;
    f.n = glm::normalize(2.0f * glm::dot(frame.n, u) * u - frame.n);
    // The tangent follows (Gram–Schmidt), so that an anisotropic lobe keeps its orientation along dp/du.
    const Vec3 s = frame.s - glm::dot(frame.s, f.n) * f.n;
    const float len = glm::length(s);
    if (!(len > 1e-6f)) return Frame(f.n);
    f.s = s / len;
    f.t = glm::cross(f.n, f.s);
    return f;
  }
  bool same_side(const Frame& f, const Vec3& wi_world) const {
    return untilted_normal == Vec3(0.0f) || glm::dot(wi_world, untilted_normal) * glm::dot(wi_world, f.n) > 0.0f;
  }
  // Estevez et al.'s shadowing term as Mitsuba's eval_shadow_terminator: 2 / (1 + √(1 + α²·tan²θi)) with
  // α² = min(tan²θn / 8, 1), θn the tilt and θi the incident direction's angle, both from the untilted normal.
  float shadowing(const Frame& f, const Vec3& wi_world) const {
    if (untilted_normal == Vec3(0.0f)) return 1.0f;
    const float cn = glm::dot(f.n, untilted_normal), ci = glm::dot(wi_world, untilted_normal);
    const float alpha2 = std::fmin(0.125f * std::fmax(0.0f, 1.0f - cn * cn) / (cn * cn), 1.0f);
    const float tan2_i = std::fmax(0.0f, 1.0f - ci * ci) / (ci * ci);
    return 2.0f / (1.0f + std::sqrt(1.0f + alpha2 * tan2_i));
  }
};

}  // namespace clr::scene
