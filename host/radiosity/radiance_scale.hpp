#pragma once
// The unit in which the N-Module learns radiance (nn::NetworkConfig::output_scale). Its initial weights, Adam's
// step sizes and the relative residual's 0.01 fit radiance of order 1: on the furnace (tests/radiosity/
// extremes_test.cpp) training in unit 1 reached the answer for emission inside the window below and missed it
// outside — far below, the 0.01 swamps L²; far above, the outputs cannot grow that far in time. Scenes inside the
// window (every shared scene) train in unit 1; outside it a power of ten brings the brightest emitter into [1, 10).
// docs/method.md, "The radiance unit"; the furnace figures are in docs/results/numerics.md.
#include "scene/scene.hpp"

namespace clr::radiosity {

// The emitters' brightest radiance (largest RGB component over area emitters and the environment; for delta
// lights, the radiance a white diffuse surface at a typical distance reflects), 0 for none.
float brightest_emission(const scene::Scene& scene);

// 1 when brightest_emission lies in [kRadianceWindowLow, kRadianceWindowHigh] (or is 0), else the power of ten
// 10^floor(log10(brightest)), which maps the brightest emitter into [1, 10).
float radiance_scale(const scene::Scene& scene);

inline constexpr float kRadianceWindowLow = 0.1f, kRadianceWindowHigh = 3e4f;

}  // namespace clr::radiosity
