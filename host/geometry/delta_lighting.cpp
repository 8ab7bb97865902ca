#include "geometry/delta_lighting.hpp"

#include <cmath>

namespace clr::geometry {

Rgb reflected_delta_light(const Geometry& geometry, const SurfacePoint& p, const scene::BsdfPoint& bsdf, const Vec3& wo,
                          const scene::DeltaLight& light, std::uint64_t* rays) {
  const scene::DeltaLight::Arrival a = light.arrive(p.position);
  if (scene::is_black(a.radiance)) return Rgb(0.0f);
  const Rgb fcos = bsdf.eval(wo, a.direction);
  if (scene::is_black(fcos)) return Rgb(0.0f);
  Ray shadow{p.spawn_origin(a.direction), 0.0f, a.direction, a.distance};
  if (std::isfinite(a.distance)) {
    // Up to just short of the light's position (t in units of the segment), by the relative margin an origin is
    // pushed off its surface: a light placed exactly on a surface would otherwise be hidden by that surface, which
    // rounding puts in front of it for most rays. Mitsuba stops its shadow rays short too.
    const Vec3 at = p.position + a.direction * a.distance;
    const float margin = std::fmin(2e-5f * std::fmax(1.0f, scene::max_component(glm::abs(at))), 0.5f * a.distance);
    shadow.direction = at - a.direction * margin - shadow.origin;
    shadow.tfar = 1.0f;
  }
  if (rays) ++*rays;
  if (geometry.occluded(shadow)) return Rgb(0.0f);
  return fcos * a.radiance;
}

Rgb reflected_delta_lights(const Geometry& geometry, const SurfacePoint& p, const scene::BsdfPoint& bsdf,
                           const Vec3& wo, std::span<const scene::DeltaLight> lights) {
  Rgb sum(0.0f);
  for (const auto& light : lights) sum += reflected_delta_light(geometry, p, bsdf, wo, light);
  return sum;
}

}  // namespace clr::geometry
