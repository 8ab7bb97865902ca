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
  // Where a bump or normal map tilted `frame`, the shading normal before it (else zero). As in Mitsuba's bumpmap and
  // normalmap, the BSDF is zero for an incident direction on one side of the tilted normal and the other side of
  // this one: a tilted frame would otherwise pass light through an opaque surface, or reflect what a glass surface
  // transmits (a bump-mapped glass rendered 14 % brighter than in Mitsuba).
  Vec3 untilted_normal{0.0f};

  Rgb eval(const Vec3& wo_world, const Vec3& wi_world) const {
    if (!same_side(wi_world)) return Rgb(0.0f);
    return bsdf->eval(at, frame.to_local(wo_world), frame.to_local(wi_world));
  }
  float pdf(const Vec3& wo_world, const Vec3& wi_world) const {
    if (!same_side(wi_world)) return 0.0f;
    return bsdf->pdf(at, frame.to_local(wo_world), frame.to_local(wi_world));
  }
  // wi in the result is in world space.
  std::optional<BsdfSample> sample(const Vec3& wo_world, float u_lobe, const Vec2& u) const {
    auto s = bsdf->sample(at, frame.to_local(wo_world), u_lobe, u);
    if (s) s->wi = frame.to_world(s->wi);
    if (s && !same_side(s->wi)) return std::nullopt;
    return s;
  }
  bool same_side(const Vec3& wi_world) const {
    return untilted_normal == Vec3(0.0f) || glm::dot(wi_world, untilted_normal) * glm::dot(wi_world, frame.n) > 0.0f;
  }
};

}  // namespace clr::scene
