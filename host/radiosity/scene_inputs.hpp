#pragma once
// What the networks' inputs need to know of a scene: the box the hash grids cover, whether albedo and roughness
// vary over the modelled surfaces (an input that is the same everywhere carries nothing), and how much surface
// the grids hold (the presets size the hash table by it).
#include <array>

#include "geometry/geometry.hpp"
#include "geometry/surface_sampler.hpp"

namespace clr::radiosity {

struct SceneInputs {
  std::array<float, 3> lo, hi;
  bool albedo_varies, roughness_varies;
  double area;  // of the modelled surfaces
};

SceneInputs scene_inputs(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler);

}  // namespace clr::radiosity
