#include "radiosity/surface_query.hpp"

namespace clr::radiosity {

void write_raw_row(const scene::Scene& scene, const geometry::SurfacePoint& p, const Vec3& wo, float* row) {
  const scene::Bsdf& bsdf = scene.bsdf(scene.shapes[p.shape]);
  const Rgb albedo = bsdf.albedo(p.at);
  const Vec3 values[4] = {p.position, wo, p.frame.n, albedo};
  for (int v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c) row[3 * v + c] = values[v][c];
  row[nn::raw::kRoughness] = bsdf.roughness();
}

PathEnd trace_to_surface(const geometry::Geometry& geometry, geometry::Ray ray, Pcg32& rng, int max_delta_bounces,
                         bool sun_on_first) {
  const scene::Scene& scene = geometry.scene();
  PathEnd end;
  for (int bounce = 0;; ++bounce) {
    const geometry::Hit hit = geometry.intersect(ray);
    const Vec3 wo = -glm::normalize(ray.direction);
    if (!hit.valid()) {
      if (scene.environment) {
        const Rgb le = end.throughput * scene.environment->eval(-wo, sun_on_first || bounce > 0);
        end.emitted += le;
        if (bounce == 0) end.first_emitted = le;
      }
      return end;
    }
    const geometry::SurfacePoint p = geometry.surface(hit);
    const Rgb le = end.throughput * geometry::emitted(scene, p, wo);
    end.emitted += le;
    if (bounce == 0 && !scene::is_black(le)) {  // an emitter: a light sample could have drawn it (no copy otherwise)
      end.first_emitted = le;
      end.first_hit = p;
    }
    const scene::BsdfPoint bsdf = p.bsdf(scene);
    if (bsdf.bsdf->has_non_delta()) {
      // The black side of a one-sided surface scatters nothing: the path ends with what it has, no lookup.
      end.at_surface = bsdf.seen_from_scattering_side(wo);
      end.point = p;
      end.wo = wo;
      return end;
    }
    if (bounce == max_delta_bounces) return end;
    const float u_lobe = rng.next_float();
    const auto s = bsdf.sample(wo, u_lobe, {rng.next_float(), rng.next_float()});
    if (!s) return end;
    end.throughput *= s->weight;
    ray = geometry::Ray{p.spawn_origin(s->wi), 0.0f, s->wi};
  }
}

}  // namespace clr::radiosity
