#include "geometry/geometry.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "common/parallel.hpp"

namespace clr::geometry {

struct Geometry::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

struct Geometry::ShapeData {
  const scene::Shape* shape;
  const scene::Texture* opacity;  // the mask's; null: opaque
};

namespace {

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
}

// A hash of the ray and the triangle in [0, 1): the alpha test's "random" number. Tied to the ray, a partially
// opaque surface is hit with probability `opacity` on average, while the same ray always sees the same answer.
float alpha_hash(std::uint32_t prim, float ox, float oy, float oz, float dx, float dy, float dz) {
  std::uint64_t h = 0x9e3779b97f4a7c15ull ^ prim;
  for (float f : {ox, oy, oz, dx, dy, dz}) {
    h ^= std::bit_cast<std::uint32_t>(f);
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
  }
  return float(h >> 40) * 0x1p-24f;
}

// Whether the mask lets primitive `prim` at `b` stop the ray (the alpha test; a sphere passes which of its two
// crossings as `prim`).
bool opaque(const Geometry::ShapeData& d, std::uint32_t prim, const Vec2& b, const float o[3], const float dir[3]) {
  if (!d.opacity) return true;
  const Rgb a = d.opacity->eval(d.shape->texture_point(prim, b));
  return alpha_hash(prim, o[0], o[1], o[2], dir[0], dir[1], dir[2]) < (a.x + a.y + a.z) / 3.0f;
}

void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* d = static_cast<const Geometry::ShapeData*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned n = args->N;
    const float o[3] = {RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i), RTCRayN_org_z(args->ray, n, i)};
    const float dir[3] = {RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i),
                          RTCRayN_dir_z(args->ray, n, i)};
    const Vec2 b(RTCHitN_u(args->hit, n, i), RTCHitN_v(args->hit, n, i));
    if (!opaque(*d, RTCHitN_primID(args->hit, n, i), b, o, dir)) args->valid[i] = 0;
  }
}

// ---- exact spheres: an Embree user geometry ----------------------------------------------------------------------

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
  const scene::Sphere& s = *static_cast<const Geometry::ShapeData*>(args->geometryUserPtr)->shape->sphere;
  // Padded by the float rounding of centre ± radius, so that the box holds every point the roots can give.
  const float pad = s.radius * 1e-6f +
                    1e-6f * std::max({std::fabs(s.center.x), std::fabs(s.center.y), std::fabs(s.center.z), s.radius});
  RTCBounds& b = *args->bounds_o;
  b.lower_x = s.center.x - s.radius - pad;
  b.lower_y = s.center.y - s.radius - pad;
  b.lower_z = s.center.z - s.radius - pad;
  b.upper_x = s.center.x + s.radius + pad;
  b.upper_y = s.center.y + s.radius + pad;
  b.upper_z = s.center.z + s.radius + pad;
}

// The first crossing of the ray with the sphere in (tnear, tfar) that the mask lets stop it: its t and uv. In double:
// a ray leaving the sphere starts a relative 2e-5 off it (SurfacePoint::spawn_origin), so the roots are near
// cancellation, which float would resolve to about that much.
bool sphere_crossing(const Geometry::ShapeData& d, const float o[3], const float dir[3], float tnear, float tfar,
                     float& t_hit, Vec2& uv) {
  const scene::Sphere& s = *d.shape->sphere;
  const double oc[3] = {double(o[0]) - s.center.x, double(o[1]) - s.center.y, double(o[2]) - s.center.z};
  const double a = double(dir[0]) * dir[0] + double(dir[1]) * dir[1] + double(dir[2]) * dir[2];
  const double b = oc[0] * dir[0] + oc[1] * dir[1] + oc[2] * dir[2];
  const double c = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - double(s.radius) * s.radius;
  const double disc = b * b - a * c;
  if (!(disc >= 0) || !(a > 0)) return false;
  // The two roots without cancellation: q = −(b + sign(b)·√disc), t = q/a and c/q.
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  double t[2] = {q / a, q != 0 ? c / q : q / a};
  if (t[0] > t[1]) std::swap(t[0], t[1]);
  for (std::uint32_t k = 0; k < 2; ++k) {
    const double tr = t[k];
    if (!(tr > tnear && tr < tfar)) continue;
    const Vec3 offset(float(oc[0] + tr * dir[0]), float(oc[1] + tr * dir[1]), float(oc[2] + tr * dir[2]));
    const Vec2 at = s.uv(offset);
    // Each crossing draws its own alpha test (k stands for the triangle a mesh would have): a ray through a masked
    // glass sphere that skipped the entry and never the exit would skip the exit's η² too, and lose 5 % of its
    // light in a white furnace.
    if (!opaque(d, k, at, o, dir)) continue;
    t_hit = float(tr);
    uv = at;
    return true;
  }
  return false;
}

void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* d = static_cast<const Geometry::ShapeData*>(args->geometryUserPtr);
  const unsigned n = args->N;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, n);
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const float o[3] = {RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i)};
    const float dir[3] = {RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i)};
    float t = 0;
    Vec2 uv;
    if (!sphere_crossing(*d, o, dir, RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i), t, uv)) continue;
    RTCRayN_tfar(ray, n, i) = t;
    const Vec3 normal = d->shape->sphere->direction(uv);
    RTCHitN_Ng_x(hit, n, i) = normal.x;
    RTCHitN_Ng_y(hit, n, i) = normal.y;
    RTCHitN_Ng_z(hit, n, i) = normal.z;
    RTCHitN_u(hit, n, i) = uv.x;
    RTCHitN_v(hit, n, i) = uv.y;
    RTCHitN_primID(hit, n, i) = args->primID;
    RTCHitN_geomID(hit, n, i) = args->geomID;
    RTCHitN_instID(hit, n, i, 0) = args->context->instID[0];
  }
}

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto* d = static_cast<const Geometry::ShapeData*>(args->geometryUserPtr);
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const float o[3] = {RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i), RTCRayN_org_z(args->ray, n, i)};
    const float dir[3] = {RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i),
                          RTCRayN_dir_z(args->ray, n, i)};
    float t = 0;
    Vec2 uv;
    if (sphere_crossing(*d, o, dir, RTCRayN_tnear(args->ray, n, i), RTCRayN_tfar(args->ray, n, i), t, uv))
      RTCRayN_tfar(args->ray, n, i) = -std::numeric_limits<float>::infinity();
  }
}

RTCRayHit to_embree(const Ray& r) {
  RTCRayHit rh;
  rh.ray.org_x = r.origin.x;
  rh.ray.org_y = r.origin.y;
  rh.ray.org_z = r.origin.z;
  rh.ray.dir_x = r.direction.x;
  rh.ray.dir_y = r.direction.y;
  rh.ray.dir_z = r.direction.z;
  rh.ray.tnear = r.tnear;
  rh.ray.tfar = r.tfar;
  rh.ray.time = 0;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

Geometry::Geometry(const scene::Scene& scene) : scene_(&scene), embree_(std::make_unique<Embree>()) {
  embree_->device = rtcNewDevice(nullptr);
  if (!embree_->device) throw std::runtime_error("Embree: cannot create a device");
  embree_->scene = rtcNewScene(embree_->device);
  rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
  for (std::size_t i = 0; i < scene.shapes.size(); ++i) {
    const scene::Shape& shape = scene.shapes[i];
    shape_data_.push_back(std::make_unique<ShapeData>(ShapeData{&shape, scene.bsdf(shape).opacity()}));
    ShapeData* data = shape_data_.back().get();
    RTCGeometry g = nullptr;
    if (shape.sphere) {
      g = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(g, 1);
      rtcSetGeometryBoundsFunction(g, sphere_bounds, nullptr);
      rtcSetGeometryIntersectFunction(g, sphere_intersect);
      rtcSetGeometryOccludedFunction(g, sphere_occluded);
      rtcSetGeometryUserData(g, data);  // the mask is tested in the callbacks themselves
    } else {
      const scene::Mesh& m = shape.mesh;
      g = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
      // Embree reads vertices with 16-byte loads: its own buffers come padded, so the mesh is copied into them.
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), m.positions.size()));
      auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.triangles.size()));
      check(embree_->device, "allocating a mesh");
      std::memcpy(v, m.positions.data(), m.positions.size() * sizeof(Vec3));
      std::memcpy(t, m.triangles.data(), m.triangles.size() * sizeof(glm::uvec3));
      if (data->opacity) {
        rtcSetGeometryUserData(g, data);
        rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
        rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
      }
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(embree_->scene, g, unsigned(i));
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(embree_->scene);
  check(embree_->device, "building the BVH");
}

Geometry::~Geometry() = default;

Hit Geometry::intersect(const Ray& ray) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = to_embree(ray);
  rtcIntersect1(embree_->scene, &ctx, &rh);
  Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.t = rh.ray.tfar;
  h.shape = rh.hit.geomID;
  h.prim = rh.hit.primID;
  h.barycentric = {rh.hit.u, rh.hit.v};
  return h;
}

bool Geometry::occluded(const Ray& ray) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r = to_embree(ray).ray;
  rtcOccluded1(embree_->scene, &ctx, &r);
  return r.tfar < 0;  // Embree marks a blocked ray with tfar = -inf
}

void Geometry::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
  if (hits.size() != rays.size()) throw std::invalid_argument("Geometry::intersect: rays and hits differ in size");
  parallel_for(rays.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) hits[i] = intersect(rays[i]);
  });
}

void Geometry::occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const {
  if (blocked.size() != rays.size()) throw std::invalid_argument("Geometry::occluded: rays and results differ in size");
  parallel_for(rays.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) blocked[i] = occluded(rays[i]) ? 1 : 0;
  });
}

}  // namespace clr::geometry
