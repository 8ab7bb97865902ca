#pragma once
// Where the network is asked for radiance: a point on a non-delta surface and an outgoing direction, written as
// one raw input row (the column layout of nn/encoder.hpp), plus the delta-bounce chain that leads there.
#include <cstdint>
#include <optional>

#include "common/pcg32.hpp"
#include "geometry/geometry.hpp"
#include "nn/encoder.hpp"

namespace clr::radiosity {

using scene::Rgb;
using scene::Vec3;

// Writes position, ω_o, shading normal, albedo and roughness of `p` seen from `wo` into row[0, kRawInputs).
void write_raw_row(const scene::Scene& scene, const geometry::SurfacePoint& p, const Vec3& wo, float* row);

// The end of a ray followed through delta (purely specular) surfaces, as rendering and training both need it:
// radiance along the ray = emitted + throughput · L_α(query) when `at_surface`, else just `emitted`.
struct PathEnd {
  Rgb throughput{1.0f};  // product of the delta bounces' weights
  Rgb emitted{0.0f};     // emission met along the chain (environment included), already weighted
  // The part of `emitted` met where the ray's first segment ended, before any delta bounce — the only part a light
  // sample from the ray's origin can also reach, so the only part multiple importance sampling reweighs — and the
  // surface there (kept only where it emits; none where the ray escaped).
  Rgb first_emitted{0.0f};
  std::optional<geometry::SurfacePoint> first_hit;
  bool at_surface = false;
  geometry::SurfacePoint point;  // valid when at_surface
  Vec3 wo{0.0f};                 // direction back along the last segment
};

// Follows `ray` until it escapes, lands on a surface with a non-delta lobe, or has made `max_delta_bounces`
// delta bounces (then it ends dark: such long specular chains carry negligible energy in practice). Landing on
// the black side of a one-sided surface ends the path without a lookup (at_surface false). `sun_on_first`: false
// where the first segment was drawn from a non-delta lobe at a point that took a sunsky's sun by next-event estimation
// (Environment::sun_as_directional): escaping there, it sees the sky only.
PathEnd trace_to_surface(const geometry::Geometry& geometry, geometry::Ray ray, Pcg32& rng, int max_delta_bounces,
                         bool sun_on_first = true);

}  // namespace clr::radiosity
