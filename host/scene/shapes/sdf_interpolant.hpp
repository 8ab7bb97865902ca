#pragma once
// The trilinear interpolant of a single-channel grid (what Mitsuba's sdfgrid intersects) and the shading normals
// Mitsuba derives from it, in grid units: sample (i, j, k) at the point (i, j, k).
#include "scene/sdf_grid.hpp"

namespace clr::scene {

class SdfInterpolant {
 public:
  explicit SdfInterpolant(const VolumeGrid& grid) : grid_(grid), last_(grid.size - 1) {}

  // The cell whose trilinear patch defines the interpolant at p (on a shared face both patches agree).
  glm::ivec3 cell_of(const Vec3& p) const;
  // The interpolant at p, from the patch of `cell` (p inside or on it).
  float value(const Vec3& p, const glm::ivec3& cell) const;
  float value(const Vec3& p) const { return value(p, cell_of(p)); }
  // Its gradient with respect to object space ([0,1]³), from the patch of `cell`.
  Vec3 gradient(const Vec3& p, const glm::ivec3& cell) const;
  // Mitsuba's `analytic` and `smooth` shading normals at p, in object space, unit length; (0, 0, 0) where the field
  // is flat and defines none.
  Vec3 analytic_normal(const Vec3& p) const;
  Vec3 smooth_normal(const Vec3& p) const;
  // Grid units per object-space unit along each axis.
  Vec3 scale() const { return Vec3(last_); }

 private:
  const VolumeGrid& grid_;
  glm::ivec3 last_;  // the highest sample index along each axis
};

}  // namespace clr::scene
