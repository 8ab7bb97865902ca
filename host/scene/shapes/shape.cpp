#include <algorithm>

#include "scene/scene.hpp"

namespace clr::scene {

double Shape::primitive_area(std::uint32_t prim) const { return exact ? exact->area() : mesh.triangle_area(prim); }

double Shape::area() const { return exact ? exact->area() : mesh.area(); }

void Shape::extend_bounds(Vec3& lo, Vec3& hi) const {
  if (exact) {
    Vec3 l, h;
    exact->bounds(l, h);
    lo = glm::min(lo, l);
    hi = glm::max(hi, h);
  }
  for (const auto& v : mesh.positions) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
}

}  // namespace clr::scene
