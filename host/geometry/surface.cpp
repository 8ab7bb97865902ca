#include "geometry/surface.hpp"

#include <algorithm>
#include <cmath>

namespace clr::geometry {
namespace {

// Height of a bump map (its luminance, like Mitsuba's single-channel evaluation of an RGB texture) at `at` moved
// by `du` in uv.
float height(const scene::BumpMap& b, scene::TexturePoint at, const Vec2& du = Vec2(0.0f)) {
  at.uv += du;
  return scene::luminance(b.height.eval(at));
}

// Tilts the shading normal by the height field's gradient as Mitsuba's bumpmap does: the tangents become dp/du and
// dp/dv with their component along the shading normal n replaced by scale·∂h, so that a flat height field keeps n
// (an interpolated normal, not the triangle's), and the result is turned to the geometric normal's side.
Vec3 bump_normal(const scene::BumpMap& b, const Vec3& n, const Vec3& geometric, const Vec3& dpdu, const Vec3& dpdv,
                 const scene::TexturePoint& at) {
  // Differences over an eighth of a texel: the derivative of the bilinear lookup within the texel, as Mitsuba's
  // analytic gradient, where a fixed 1e-3 spanned two texels of a 2048² map and smoothed the bumps away.
  const float delta = std::clamp(b.height.texel_uv() / 8.0f, 1e-5f, 1e-3f);
  const float h = height(b, at);
  const float dhdu = (height(b, at, Vec2(delta, 0)) - h) / delta;
  const float dhdv = (height(b, at, Vec2(0, delta)) - h) / delta;
  const Vec3 tu = dpdu + (b.scale * dhdu - glm::dot(n, dpdu)) * n, tv = dpdv + (b.scale * dhdv - glm::dot(n, dpdv)) * n;
  Vec3 bumped = glm::cross(tu, tv);
  const float len = glm::length(bumped);
  if (!(len > 0)) return n;
  bumped /= len;
  return glm::dot(bumped, geometric) < 0 ? -bumped : bumped;
}

}  // namespace

Vec3 SurfacePoint::spawn_origin(const Vec3& dir) const {
  // The magnitude once had a floor of 1: an absolute 2e-5 that is 0.5 % of a wall in a scene 4e-3 across, and would
  // jump over whole walls below that. The triangle's own extent bounds the error instead; a hand-built point
  // (extent 0) at the origin keeps the old floor.
  const float magnitude = std::max({std::fabs(position.x), std::fabs(position.y), std::fabs(position.z), extent});
  const float offset = 2e-5f * (magnitude > 0 ? magnitude : 1.0f);
  return position + geometric_normal * (glm::dot(geometric_normal, dir) > 0 ? offset : -offset);
}

namespace {

// The geometry of a point before shading: position, normals and uv tangents (lazily, only where a bump map, normal
// map or anisotropic lobe needs them).
struct Local {
  Vec3 n;  // interpolated normal
  Vec3 dpdu{0.0f}, dpdv{0.0f};
  bool have_uv = false;
};

Local on_triangle(const scene::Mesh& m, std::uint32_t prim, const Vec2& b, bool need_tangents, SurfacePoint& p) {
  const glm::uvec3 t = m.triangles[prim];
  const float b0 = 1.0f - b.x - b.y;
  const Vec3 p0 = m.positions[t.x], p1 = m.positions[t.y], p2 = m.positions[t.z];
  p.position = b0 * p0 + b.x * p1 + b.y * p2;
  const Vec3 largest = glm::max(glm::max(glm::abs(p0), glm::abs(p1)), glm::abs(p2));
  p.extent = std::max({largest.x, largest.y, largest.z});
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const Vec3 ng = glm::cross(e1, e2);
  const float len = glm::length(ng);
  p.geometric_normal = len > 0 ? ng / len : Vec3(0, 0, 1);
  Local l{p.geometric_normal};
  if (!m.normals.empty()) {
    const Vec3 ns = b0 * m.normals[t.x] + b.x * m.normals[t.y] + b.y * m.normals[t.z];
    const float nl = glm::length(ns);
    if (nl > 0) l.n = ns / nl;
  }
  p.at = m.texture_point(prim, b);
  // dp/du and dp/dv from the triangle's uv parametrisation; without uvs (or with a degenerate map) the frame's own
  // tangent stands in for dp/du and bump mapping is skipped.
  if (need_tangents && !m.uvs.empty()) {
    const Vec2 d1 = m.uvs[t.y] - m.uvs[t.x], d2 = m.uvs[t.z] - m.uvs[t.x];
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (std::fabs(det) > 1e-12f) {
      l.dpdu = (d2.y * e1 - d1.y * e2) / det;
      l.dpdv = (d1.x * e2 - d2.x * e1) / det;
      l.have_uv = true;
    }
  }
  return l;
}

Local on_exact(const scene::ExactShape& s, const Vec2& uv, bool need_tangents, SurfacePoint& p) {
  p.position = s.position(uv);
  Vec3 lo, hi;
  s.bounds(lo, hi);
  const Vec3 big = glm::max(glm::abs(lo), glm::abs(hi));
  p.extent = std::max({big.x, big.y, big.z});
  p.geometric_normal = s.normal(uv);
  p.at = scene::TexturePoint(uv);
  Local l{p.geometric_normal};
  if (need_tangents) {
    s.tangents(uv, l.dpdu, l.dpdv);
    l.have_uv = true;
  }
  return l;
}

}  // namespace

SurfacePoint surface_point(const scene::Scene& scene, std::uint32_t shape, std::uint32_t prim, const Vec2& b) {
  const scene::Shape& s = scene.shapes[shape];
  const scene::Bsdf& bsdf = scene.bsdf(s);
  const auto* bump = bsdf.bump();
  const auto* normal_map = bsdf.normal_map();
  const bool need_tangents = bump || normal_map || bsdf.anisotropic();
  SurfacePoint p;
  p.shape = shape;
  p.prim = prim;
  const Local l = s.exact ? on_exact(*s.exact, b, need_tangents, p) : on_triangle(s.mesh, prim, b, need_tangents, p);
  Vec3 n = l.n;
  if (!need_tangents) {
    p.frame = scene::Frame(n);
    return p;
  }
  if (bump && l.have_uv) n = bump_normal(*bump, n, p.geometric_normal, l.dpdu, l.dpdv, p.at);
  // The shading frame Mitsuba uses for normal maps and anisotropic lobes: s = dp/du made orthogonal to n.
  auto tangent_frame = [&](const Vec3& normal) {
    const Vec3 s_raw = l.dpdu - normal * glm::dot(normal, l.dpdu);
    const float len = glm::length(s_raw);
    if (!l.have_uv || !(len > 1e-12f)) return scene::Frame(normal);
    scene::Frame f;
    f.n = normal;
    f.s = s_raw / len;
    f.t = glm::cross(normal, f.s);
    return f;
  };
  if (normal_map) {
    // Mitsuba: n' = the texture's raw RGB mapped from [0, 1] to [-1, 1], in the tangent frame of the shading normal.
    const Vec3 local = 2.0f * normal_map->eval(p.at) - 1.0f;
    const float len = glm::length(local);
    if (len > 0) n = glm::normalize(tangent_frame(n).to_world(local / len));
  }
  p.frame = normal_map || bsdf.anisotropic() ? tangent_frame(n) : scene::Frame(n);
  if (n != l.n) p.untilted_normal = l.n;
  return p;
}

SurfacePoint uniform_surface_point(const scene::Scene& scene, std::uint32_t shape, std::uint32_t prim, const Vec2& u) {
  if (const auto& exact = scene.shapes[shape].exact) return surface_point(scene, shape, prim, exact->uniform_uv(u));
  // Uniform barycentrics: (1 − √ξ1, √ξ1·ξ2) spreads ξ evenly over the triangle's area.
  const float su = std::sqrt(u.x);
  return surface_point(scene, shape, prim, Vec2(su * (1.0f - u.y), su * u.y));
}

Rgb emitted(const scene::Scene& scene, const SurfacePoint& p, const Vec3& wo) {
  const scene::Shape& s = scene.shapes[p.shape];
  if (!s.is_emitter() || glm::dot(p.frame.n, wo) <= 0) return Rgb(0.0f);
  return s.radiance_texture ? s.radiance_texture->eval(p.at) : s.radiance;
}

}  // namespace clr::geometry
