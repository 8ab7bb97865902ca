#include "geometry/geometry.hpp"

#include <embree3/rtcore.h>

#include <bit>
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

struct Geometry::Masked {
  const scene::Mesh* mesh;
  const scene::Texture* opacity;
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

void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* m = static_cast<const Geometry::Masked*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    const Vec2 b(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
    const Rgb o = m->opacity->eval(m->mesh->texture_point(prim, b));
    const float alpha = (o.x + o.y + o.z) / 3.0f;
    const float h = alpha_hash(prim, RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                               RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                               RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i));
    if (h >= alpha) args->valid[i] = 0;
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
    const scene::Mesh& m = scene.shapes[i].mesh;
    RTCGeometry g = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads vertices with 16-byte loads: its own buffers come padded, so the mesh is copied into them.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.positions.size()));
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), m.triangles.size()));
    check(embree_->device, "allocating a mesh");
    std::memcpy(v, m.positions.data(), m.positions.size() * sizeof(Vec3));
    std::memcpy(t, m.triangles.data(), m.triangles.size() * sizeof(glm::uvec3));
    if (const scene::Texture* opacity = scene.bsdf(scene.shapes[i]).opacity()) {
      masked_.push_back(std::make_unique<Masked>(Masked{&m, opacity}));
      rtcSetGeometryUserData(g, masked_.back().get());
      rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
      rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
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
