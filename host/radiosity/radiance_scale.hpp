#pragma once
// The unit in which the N-Module learns radiance (nn::NetworkConfig::output_scale). Its initial weights, Adam's
// step sizes and the relative residual's 0.01 fit radiance of order 1: on the furnace (tests/radiosity/
// extremes_test.cpp's small network, 300 steps, unit 1) the image mean came within 1.6 % for emission from 0.1 to
// 3e4, but 14 % off at 0.01 (the 0.01 swamps L² there), 2.8× off at 1e-3, 7 % off at 5e4 and 27 % at 1e5 (the
// outputs cannot grow that far in time). With the unit below, 1e-4 to 1e6 all came within 0.33 %. Scenes inside
// the window — every scene measured so far: the Cornell box's 17, the Veach scenes' 523 to 12048 — train exactly as
// before (unit 1); outside it a power of ten brings the brightest emitter into [1, 10).
#include "scene/scene.hpp"

namespace clr::radiosity {

// The emitters' brightest radiance (largest RGB component over area emitters and the environment), 0 for none.
float brightest_emission(const scene::Scene& scene);

// 1 when brightest_emission lies in [kRadianceWindowLow, kRadianceWindowHigh] (or is 0), else the power of ten
// 10^floor(log10(brightest)), which maps the brightest emitter into [1, 10).
float radiance_scale(const scene::Scene& scene);

inline constexpr float kRadianceWindowLow = 0.1f, kRadianceWindowHigh = 3e4f;

}  // namespace clr::radiosity
