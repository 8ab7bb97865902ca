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
    // Up to the light's position, where nothing can be hit: t in units of the whole segment.
    shadow.direction = p.position + a.direction * a.distance - shadow.origin;
    shadow.tfar = 1.0f;
  }
  if (rays) ++*rays;
  if (geometry.occluded(shadow)) return Rgb(0.0f);
  return fcos * a.radiance;
}

Rgb reflected_delta_lights(const Geometry& geometry, const SurfacePoint& p, const scene::BsdfPoint& bsdf,
                           const Vec3& wo) {
  Rgb sum(0.0f);
  for (const auto& light : geometry.scene().delta_lights) sum += reflected_delta_light(geometry, p, bsdf, wo, light);
  return sum;
}

}  // namespace clr::geometry
