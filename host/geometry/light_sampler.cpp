#include "geometry/light_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/delta_lighting.hpp"

namespace clr::geometry {
namespace {

// 1 − cos θmax of the cone in which a sphere light that emits outwards is seen from `from`, or 0 where it is drawn by
// area instead (`from` on or inside it, or a sphere that emits inwards). Within the cone every direction meets its
// near, lit side: drawing directions there, as Mitsuba does, wastes none on the far side as area sampling does.
double cone_width(const scene::Shape& shape, const Vec3& from) {
  const auto& s = shape.exact;
  if (!s || s->kind != scene::ExactShape::Kind::sphere || s->flip) return 0;
  const glm::dvec3 d = glm::dvec3(s->origin) - glm::dvec3(from);
  const double d2 = glm::dot(d, d), r2 = double(s->radius()) * s->radius();
  if (!(d2 > r2 * (1 + 1e-4))) return 0;
  const double sin2 = r2 / d2;
  return sin2 / (1 + std::sqrt(1 - sin2));  // without the cancellation of 1 − √(1 − sin²)
}

// The uv of the point where a direction drawn uniformly within that cone (1 − cos θmax = `width`) from two uniforms
// first meets the sphere (the near root, in double).
scene::Vec2 uv_in_cone(const scene::ExactShape& s, const Vec3& from, double width, const scene::Vec2& u) {
  const glm::dvec3 axis = glm::normalize(glm::dvec3(s.origin) - glm::dvec3(from));
  const double one_minus_cos = double(u.x) * width, cos_t = 1 - one_minus_cos;
  const double sin_t = std::sqrt(std::fmax(0.0, one_minus_cos * (2 - one_minus_cos))), phi = 2 * M_PI * double(u.y);
  const scene::Frame frame{Vec3(axis)};
  const glm::dvec3 dir = glm::normalize(
      glm::dvec3(frame.to_world(Vec3(float(sin_t * std::cos(phi)), float(sin_t * std::sin(phi)), float(cos_t)))));
  const glm::dvec3 oc = glm::dvec3(from) - glm::dvec3(s.origin);
  const double o[3] = {from.x, from.y, from.z}, d[3] = {dir.x, dir.y, dir.z};
  double t[2];
  // A direction at the cone's rim may graze past by rounding: then its closest approach, on the rim.
  return s.uv(oc + (s.crossings(o, d, t) > 0 ? t[0] : -glm::dot(oc, dir)) * dir);
}

}  // namespace

LightSampler::LightSampler(const scene::Scene& scene, LightChoice choice)
    : scene_(&scene),
      environment_(choice.environment ? scene.environment.get() : nullptr),
      delta_lights_(choice.delta ? scene.delta_lights.size() : 0),
      first_(scene.shapes.size(), std::numeric_limits<std::size_t>::max()) {
  for (std::size_t s = 0; s < scene.shapes.size(); ++s) {
    const auto& shape = scene.shapes[s];
    if (!shape.is_emitter()) continue;
    first_[s] = cdf_.size();
    for (std::size_t t = 0; t < shape.primitive_count(); ++t) {
      const auto a = float(shape.primitive_area(std::uint32_t(t)));
      total_ += double(a) * double(scene::luminance(shape.radiance));
      shape_.push_back(std::uint32_t(s));
      prim_.push_back(std::uint32_t(t));
      area_.push_back(a);
      cdf_.push_back(total_);
    }
  }
  if (!(total_ > 0)) {
    cdf_.clear();
    shape_.clear();
    prim_.clear();
    area_.clear();
  }
  // Each kind of light gets an equal share: the environment's power is not comparable to the triangles' (it has
  // no area), nor a point light's, and an even split never starves any.
  const std::size_t shares = (cdf_.empty() ? 0 : 1) + (environment_ ? 1 : 0) + delta_lights_;
  if (shares == 0) return;
  const float share = 1.0f / float(shares);
  if (environment_) environment_probability_ = share;
  if (!cdf_.empty()) area_probability_ = share;
  delta_probability_ = share;
}

LightSample LightSampler::sample(const Vec3& from, Pcg32& rng) const {
  LightSample ls{};
  const float u_select = rng.next_float();
  const scene::Vec2 u(rng.next_float(), rng.next_float());
  if (u_select < environment_probability_) {
    const auto s = environment_->sample(u);
    ls.direction = s.dir;
    ls.distance = std::numeric_limits<float>::infinity();
    ls.radiance = s.radiance;
    ls.pdf = s.pdf * environment_probability_;
    ls.environment = true;
    return ls;
  }
  if (u_select >= environment_probability_ + area_probability_) {
    const auto& lights = scene_->delta_lights;
    const auto i = std::min(std::size_t((u_select - environment_probability_ - area_probability_) / delta_probability_),
                            delta_lights_ - 1);
    const auto a = lights[i].arrive(from);
    ls.direction = a.direction;
    ls.distance = a.distance;
    ls.point = from + a.direction * a.distance;
    ls.radiance = a.radiance;
    ls.pdf = delta_probability_;
    ls.environment = std::isinf(a.distance);
    ls.delta = true;
    ls.delta_light = &lights[i];
    return ls;
  }
  const double target = double(rng.next_float()) * total_;
  const auto k = std::size_t(std::min<std::ptrdiff_t>(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin(),
                                                      std::ptrdiff_t(cdf_.size()) - 1));
  const scene::Shape& shape = scene_->shapes[shape_[k]];
  const double width = cone_width(shape, from);
  const auto p = width > 0
                     ? geometry::surface_point(*scene_, shape_[k], prim_[k], uv_in_cone(*shape.exact, from, width, u))
                     : geometry::uniform_surface_point(*scene_, shape_[k], prim_[k], u);
  const Vec3 d = p.position - from;
  ls.distance = glm::length(d);
  if (!(ls.distance > 0)) return ls;
  ls.direction = d / ls.distance;
  ls.point = p.position;
  ls.light_normal = p.geometric_normal;
  ls.radiance = geometry::emitted(*scene_, p, -ls.direction);
  ls.pdf = pdf_triangle(p, from);  // the density MIS is told, so the two agree by construction
  return ls;
}

float LightSampler::pdf_triangle(const geometry::SurfacePoint& p, const Vec3& from) const {
  const std::size_t first = first_[p.shape];
  if (first == std::numeric_limits<std::size_t>::max() || cdf_.empty()) return 0.0f;
  const std::size_t k = first + p.prim;
  const float select = float((cdf_[k] - (k ? cdf_[k - 1] : 0.0)) / total_) * area_probability_;
  if (const double width = cone_width(scene_->shapes[p.shape], from); width > 0)
    return float(double(select) / (2 * M_PI * width));
  const Vec3 d = p.position - from;
  const float dist2 = glm::dot(d, d);
  const float cos_light = std::fabs(glm::dot(p.geometric_normal, d)) / std::sqrt(dist2);
  if (!(cos_light > 0)) return 0.0f;
  return select / area_[k] * dist2 / cos_light;
}

float LightSampler::pdf_environment(const Vec3& dir) const {
  return environment_probability_ > 0 ? environment_probability_ * environment_->pdf(dir) : 0.0f;
}

Rgb next_event(const Geometry& geometry, const LightSampler& lights, const SurfacePoint& p,
               const scene::BsdfPoint& bsdf, const Vec3& wo, Pcg32& rng, std::uint64_t* rays) {
  const LightSample ls = lights.sample(p.position, rng);
  if (!(ls.pdf > 0) || scene::is_black(ls.radiance)) return Rgb(0.0f);
  if (ls.delta) return reflected_delta_light(geometry, p, bsdf, wo, *ls.delta_light, rays) / ls.pdf;
  const Rgb f = bsdf.eval(wo, ls.direction);
  if (scene::is_black(f)) return Rgb(0.0f);
  Ray shadow{p.spawn_origin(ls.direction), 0.0f, ls.direction, ls.distance};
  if (!ls.environment) {
    // Stop short of the light's surface by the same relative margin the origin was pushed off its own.
    const Vec3 target = ls.point + ls.light_normal * (glm::dot(ls.light_normal, -ls.direction) > 0 ? 1.0f : -1.0f) *
                                       2e-5f * std::fmax(1.0f, scene::max_component(glm::abs(ls.point)));
    shadow.direction = target - shadow.origin;
    shadow.tfar = 1.0f;
  }
  if (rays) ++*rays;
  if (geometry.occluded(shadow)) return Rgb(0.0f);
  const float w = power_heuristic(ls.pdf, bsdf.pdf(wo, ls.direction));
  return f * ls.radiance * (w / ls.pdf);
}

}  // namespace clr::geometry
