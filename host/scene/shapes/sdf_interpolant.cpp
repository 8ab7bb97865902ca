#include "scene/shapes/sdf_interpolant.hpp"

#include <cmath>

namespace clr::scene {
namespace {
Vec3 unit_or_zero(const Vec3& v) {
  const float len = glm::length(v);
  return len > 0 && std::isfinite(len) ? v / len : Vec3(0.0f);
}
}  // namespace

glm::ivec3 SdfInterpolant::cell_of(const Vec3& p) const {
  return glm::clamp(glm::ivec3(glm::floor(p)), glm::ivec3(0), last_ - 1);
}

float SdfInterpolant::value(const Vec3& p, const glm::ivec3& c) const {
  const Vec3 w = p - Vec3(c);
  float s[8];  // the cell's corners, indexed x + 2y + 4z
  for (int i = 0; i < 8; ++i) s[i] = grid_.at(c.x + (i & 1), c.y + (i >> 1 & 1), c.z + (i >> 2));
  const float y0 = std::lerp(std::lerp(s[0], s[1], w.x), std::lerp(s[2], s[3], w.x), w.y);
  const float y1 = std::lerp(std::lerp(s[4], s[5], w.x), std::lerp(s[6], s[7], w.x), w.y);
  return std::lerp(y0, y1, w.z);
}

Vec3 SdfInterpolant::gradient(const Vec3& p, const glm::ivec3& c) const {
  const Vec3 w = p - Vec3(c);
  Vec3 g;
  // Along axis a: the difference between the cell's two faces across a, bilinear in the other two coordinates.
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, d = (a + 2) % 3;
    float diff[4];  // indexed (offset along b) + 2 (offset along d)
    for (int i = 0; i < 4; ++i) {
      glm::ivec3 lo = c;
      lo[b] += i & 1;
      lo[d] += i >> 1;
      glm::ivec3 hi = lo;
      hi[a] += 1;
      diff[i] = grid_.at(hi.x, hi.y, hi.z) - grid_.at(lo.x, lo.y, lo.z);
    }
    g[a] = std::lerp(std::lerp(diff[0], diff[1], w[b]), std::lerp(diff[2], diff[3], w[b]), w[d]);
  }
  return g * scale();
}

Vec3 SdfInterpolant::analytic_normal(const Vec3& p) const { return unit_or_zero(gradient(p, cell_of(p))); }

// Hansson-Söderlund, Evans and Akenine-Möller 2022 (JCGT 11(3)), as Mitsuba 3 shades sdfgrids by default: each of
// the eight voxels around the sample nearest p has a normal, its gradient made of the differences across the voxel
// of the interpolant on its two sample planes along each axis, taken at p's other two coordinates; those normals
// are blended trilinearly by p's position between the voxels' centres. Being continuous in p, it shades the mesh
// smoothly across voxel faces, where the interpolant's own gradient jumps.
Vec3 SdfInterpolant::smooth_normal(const Vec3& p) const {
  const glm::ivec3 v = glm::ivec3(glm::round(p)) - 1;  // the lowest of the eight voxels
  Vec3 t = p - Vec3(v) - 0.5f;                         // p relative to that voxel's centre, in [0,1]³
  // Voxels beyond the grid have no normal: their axis' weight goes wholly to the voxel inside.
  for (int a = 0; a < 3; ++a) {
    if (v[a] < 0) t[a] = 1.0f;
    if (v[a] + 1 > last_[a] - 1) t[a] = 0.0f;
  }
  const auto plane = [&](int axis, int index) {  // the interpolant on a sample plane, at p's other coordinates
    Vec3 q = p;
    q[axis] = float(index);
    return value(q);
  };
  Vec3 sum(0.0f);
  for (int i = 0; i < 8; ++i) {
    const glm::ivec3 o(i & 1, i >> 1 & 1, i >> 2);
    const Vec3 w = glm::mix(Vec3(1.0f) - t, t, Vec3(o));
    const float weight = w.x * w.y * w.z;
    if (!(weight > 0)) continue;  // also every voxel beyond the grid
    const glm::ivec3 voxel = v + o;
    Vec3 g;
    for (int a = 0; a < 3; ++a) g[a] = plane(a, voxel[a] + 1) - plane(a, voxel[a]);
    sum += weight * unit_or_zero(g * scale());
  }
  return unit_or_zero(sum);
}

}  // namespace clr::scene
