#pragma once
// Points drawn uniformly by area over the surfaces a Neural Radiosity model learns: every shape whose BSDF has a
// non-delta lobe (purely specular surfaces are followed at render time instead, docs/design.md §2). One batched call
// per training step; sample i depends only on (seed, i), so batches are reproducible and split freely over threads.
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/surface.hpp"

namespace clr::geometry {

struct SurfaceSample {
  SurfacePoint point;      // position, geometric normal, shading frame (normal = frame.n), uv, shape, prim
  Rgb albedo;              // Bsdf::albedo at the point
  float roughness;         // Bsdf::roughness
  std::uint32_t material;  // index into Scene::materials
};

class SurfaceSampler {
 public:
  // Keeps a reference to `scene`. InputError when no shape has a non-delta BSDF.
  explicit SurfaceSampler(const scene::Scene& scene);

  // Fills `out` (any size) with independent area-uniform samples; the density is 1 / total_area(). out[i] is
  // sample first + i of the seed's sequence, so slices of one sequence can be drawn apart (MPI ranks).
  void sample(std::uint64_t seed, std::span<SurfaceSample> out, std::size_t first = 0) const;
  std::vector<SurfaceSample> sample(std::uint64_t seed, std::size_t count) const;
  double total_area() const { return total_area_; }

 private:
  const scene::Scene* scene_;
  std::vector<std::uint32_t> shape_, prim_;  // the candidate triangles
  std::vector<double> cdf_;                  // cumulative area, cdf_.back() == total_area_
  double total_area_ = 0;
};

}  // namespace clr::geometry
