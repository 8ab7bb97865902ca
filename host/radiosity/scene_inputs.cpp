#include "radiosity/scene_inputs.hpp"

#include <limits>
#include <set>

namespace clr::radiosity {

SceneInputs scene_inputs(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler) {
  // The hash grid covers the bounding box of the modelled surfaces, padded a little so points on its faces
  // are interior to the grid.
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  std::set<std::array<float, 3>> albedos;
  std::set<float> roughness;
  for (const auto& s : sampler.sample(0x5eed, 4096)) {
    lo = glm::min(lo, s.point.position);
    hi = glm::max(hi, s.point.position);
    albedos.insert({s.albedo.x, s.albedo.y, s.albedo.z});
    roughness.insert(s.roughness);
  }
  for (const auto& shape : geometry.scene().shapes) shape.extend_bounds(lo, hi);
  const glm::vec3 pad = 1e-3f * (hi - lo) + 1e-6f;
  lo -= pad;
  hi += pad;
  return {{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}, albedos.size() > 1, roughness.size() > 1, sampler.total_area()};
}

}  // namespace clr::radiosity
