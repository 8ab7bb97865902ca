#pragma once
// The I-Module (ISNR §4): its network for a scene, the frame its lobes live in, and reading a trained one back. Its
// output head, the vMF mixture with the KL / IKL gradients, is vmf_mixture.hpp; the incident directions it guides
// are drawn in incident_sampling.hpp.
#include <array>
#include <filesystem>
#include <glm/glm.hpp>
#include <memory>

#include "geometry/geometry.hpp"
#include "geometry/surface_sampler.hpp"
#include "nn/network.hpp"
#include "radiosity/train_config.hpp"

namespace clr::radiosity {

// I-Module = hash grid (4 levels, 2^16) + SH(ω_o) + SH(n) + roughness → 3 × 64 ReLU → 32 raw outputs (8 vMF lobes).
nn::NetworkConfig i_module_config(const std::array<float, 3>& bbox_lo, const std::array<float, 3>& bbox_hi);

// The I-Module for a scene: i_module_config over its bounding box, roughness only where it varies, and the user's
// `guide` overrides (TrainConfig::guide, a JSON merge patch) on top.
// The I-Module's shape, which the mixture kernels assume: kVmfRaw outputs (8 lobes × 4). InputError naming the
// setting otherwise; checked where one is made and where a run's is read back.
void require_guide_network(const nn::NetworkConfig& config);

nn::NetworkConfig guide_network_config(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler,
                                       const TrainConfig& config);

// The normal the lobes' frame is built about: the shading normal on the side of ω_o (two-sided surfaces are lit
// from either side; the light a point sees comes from its side).
inline glm::vec3 frame_normal(const glm::vec3& n, const glm::vec3& wo) { return glm::dot(n, wo) < 0.0f ? -n : n; }

}  // namespace clr::radiosity
