#pragma once
// Named optical constants accepted where Mitsuba accepts a name instead of a number.
#include <optional>
#include <string>

#include "scene/frame.hpp"

namespace clr::scene {

std::optional<float> dielectric_ior(const std::string& name);  // "bk7", "water", "air", ...

struct ComplexIor {
  Rgb eta, k;
};
std::optional<ComplexIor> conductor_ior(const std::string& name);  // "Al", "Cu", "Au", "Ag", ..., "none"

}  // namespace clr::scene
