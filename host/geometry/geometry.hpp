#pragma once
// The scene's triangles and exact shapes (spheres, cylinders, disks) in an Embree 3 BVH: closest-hit and any-hit
// queries, one ray at a time or as a batch spread over all cores. Masked surfaces (Mitsuba's `mask`) are cut out by an
// alpha test in Embree's filter functions, so every query sees the same holes.
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "geometry/surface.hpp"

namespace clr::geometry {

struct Ray {
  Vec3 origin;
  float tnear = 0.0f;
  Vec3 direction;  // need not be unit; t is measured in its units
  float tfar = std::numeric_limits<float>::infinity();
};

inline constexpr std::uint32_t kNoHit = 0xffffffffu;

struct Hit {
  float t = std::numeric_limits<float>::infinity();
  std::uint32_t shape = kNoHit;  // index into Scene::shapes
  std::uint32_t prim = 0;        // triangle within the shape (0 on an exact shape)
  Vec2 barycentric{0.0f};        // weights of the triangle's vertices 1 and 2, or the exact shape's uv
  bool valid() const { return shape != kNoHit; }
};

class Geometry {
 public:
  // Keeps a reference to `scene`, which must outlive the Geometry.
  explicit Geometry(const scene::Scene& scene);
  ~Geometry();
  Geometry(const Geometry&) = delete;
  Geometry& operator=(const Geometry&) = delete;

  Hit intersect(const Ray& ray) const;
  bool occluded(const Ray& ray) const;
  // Batches on all hardware threads; hits[i] answers rays[i].
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const;

  SurfacePoint surface(const Hit& hit) const { return surface_point(*scene_, hit.shape, hit.prim, hit.barycentric); }
  const scene::Scene& scene() const { return *scene_; }

  struct ShapeData;  // what Embree's callbacks read of a shape: its exact shape, its mask

 private:
  const scene::Scene* scene_;
  struct Embree;
  std::unique_ptr<Embree> embree_;
  std::vector<std::unique_ptr<ShapeData>> shape_data_;
};

}  // namespace clr::geometry
