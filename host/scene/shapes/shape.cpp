#include <algorithm>

#include "scene/scene.hpp"

namespace clr::scene {

double Shape::primitive_area(std::uint32_t prim) const { return sphere ? sphere->area() : mesh.triangle_area(prim); }

double Shape::area() const { return sphere ? sphere->area() : mesh.area(); }

void Shape::extend_bounds(Vec3& lo, Vec3& hi) const {
  if (sphere) {
    lo = glm::min(lo, sphere->center - sphere->radius);
    hi = glm::max(hi, sphere->center + sphere->radius);
  }
  for (const auto& v : mesh.positions) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
}

}  // namespace clr::scene
