#include "radiosity/guide/i_module.hpp"

#include "common/error.hpp"
#include "radiosity/guide/vmf_mixture.hpp"
#include "radiosity/scene_inputs.hpp"

namespace clr::radiosity {

nn::NetworkConfig i_module_config(const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
  nn::NetworkConfig c;
  c.encoder.grid->bbox_lo = lo;
  c.encoder.grid->bbox_hi = hi;
  c.encoder.albedo = false;
  c.encoder.roughness = true;
  // A coarser, smaller grid than the N-Module's (12 levels, 2^18): the incident light's directional
  // distribution varies more slowly over the surfaces than radiance does, and the I-Module must stay a small
  // share of a step. 4 levels of 16, 35, 77, 170 cells across the scene halved the I-Module's backward against 8
  // levels to 273 cells and lowered the RHS variance of the guide trained alone (docs/results/isnr.md).
  c.encoder.grid->levels = 4;
  c.encoder.grid->growth = 2.2f;
  c.encoder.grid->log2_table = 16;
  c.width = 64;
  c.hidden_layers = 3;
  c.outputs = 32;
  c.output_activation = nn::OutputActivation::None;
  return c;
}

nn::NetworkConfig guide_network_config(const geometry::Geometry& geometry, const geometry::SurfaceSampler& sampler,
                                       const TrainConfig& config) {
  const SceneInputs in = scene_inputs(geometry, sampler);
  nn::NetworkConfig base = i_module_config(in.lo, in.hi);
  base.encoder.roughness = in.roughness_varies;
  base.seed = config.seed + 1;  // apart from the N-Module's initial parameters
  const nn::NetworkConfig c = nn::merge_patch(base, config.guide);
  require_guide_network(c);
  return c;
}

void require_guide_network(const nn::NetworkConfig& config) {
  if (config.outputs != kVmfRaw)
    throw InputError("guide.outputs must be " + std::to_string(kVmfRaw) + " (8 vMF lobes × 4), got " +
                     std::to_string(config.outputs));
}

}  // namespace clr::radiosity
