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

// Whether the mask lets primitive `prim` at `b` stop the ray (the alpha test; an exact shape passes which of its
// crossings as `prim`).
bool opaque(const Geometry::ShapeData& d, std::uint32_t prim, const Vec2& b, const float o[3], const float dir[3]) {
  if (!d.opacity) return true;
  const float a = d.opacity->eval_1(d.shape->texture_point(prim, b));
  return alpha_hash(prim, o[0], o[1], o[2], dir[0], dir[1], dir[2]) < a;
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

// ---- exact shapes (spheres, cylinders, disks): an Embree user geometry ------------------------------------------

void exact_bounds(const RTCBoundsFunctionArguments* args) {
  const scene::ExactShape& s = *static_cast<const Geometry::ShapeData*>(args->geometryUserPtr)->shape->exact;
  Vec3 lo, hi;
  s.bounds(lo, hi);
  // Padded by the float rounding of the box's coordinates, so that it holds every point the roots can give.
  const Vec3 big = glm::max(glm::abs(lo), glm::abs(hi));
  const float pad = 1e-6f * std::max({big.x, big.y, big.z, glm::length(hi - lo)});
  RTCBounds& b = *args->bounds_o;
  b.lower_x = lo.x - pad;
  b.lower_y = lo.y - pad;
  b.lower_z = lo.z - pad;
  b.upper_x = hi.x + pad;
  b.upper_y = hi.y + pad;
  b.upper_z = hi.z + pad;
}

// The first crossing of the ray with the shape in (tnear, tfar) that the mask lets stop it: its t and uv.
bool exact_crossing(const Geometry::ShapeData& d, const float o[3], const float dir[3], float tnear, float tfar,
                    float& t_hit, Vec2& uv) {
  const scene::ExactShape& s = *d.shape->exact;
  const double od[3] = {o[0], o[1], o[2]}, dd[3] = {dir[0], dir[1], dir[2]};
  double t[2];
  const int n = s.crossings(od, dd, t);
  for (int k = 0; k < n; ++k) {
    if (!(t[k] > tnear && t[k] < tfar)) continue;
    const Vec2 at = s.uv(glm::dvec3(od[0] - s.origin.x + t[k] * dd[0], od[1] - s.origin.y + t[k] * dd[1],
                                    od[2] - s.origin.z + t[k] * dd[2]));
    // Each crossing draws its own alpha test (k stands for the triangle a mesh would have): a ray through a masked
    // glass sphere that skipped the entry and never the exit would skip the exit's η² too, and lose 5 % of its
    // light in a white furnace.
    if (!opaque(d, std::uint32_t(k), at, o, dir)) continue;
    t_hit = float(t[k]);
    uv = at;
    return true;
  }
  return false;
}

void exact_intersect(const RTCIntersectFunctionNArguments* args) {
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
    if (!exact_crossing(*d, o, dir, RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i), t, uv)) continue;
    RTCRayN_tfar(ray, n, i) = t;
    const Vec3 normal = d->shape->exact->normal(uv);
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

void exact_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto* d = static_cast<const Geometry::ShapeData*>(args->geometryUserPtr);
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const float o[3] = {RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i), RTCRayN_org_z(args->ray, n, i)};
    const float dir[3] = {RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i),
                          RTCRayN_dir_z(args->ray, n, i)};
    float t = 0;
    Vec2 uv;
    if (exact_crossing(*d, o, dir, RTCRayN_tnear(args->ray, n, i), RTCRayN_tfar(args->ray, n, i), t, uv))
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
    if (shape.exact) {
      g = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(g, 1);
      rtcSetGeometryBoundsFunction(g, exact_bounds, nullptr);
      rtcSetGeometryIntersectFunction(g, exact_intersect);
      rtcSetGeometryOccludedFunction(g, exact_occluded);
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
