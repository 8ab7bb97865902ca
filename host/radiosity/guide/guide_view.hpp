#pragma once
// What the I-Module learned at one surface point, as path-guiding tools show it: the mixture q_γ(ω | x, ω_o) beside
// the target it is trained towards, p(ω) = lum(f·cos·L_i(ω)) / F with L_i = Le + L_α read from the N-Module, both
// as lat-long maps of the sphere about the shading normal (top row: the normal, bottom row: its opposite).
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "nn/network.hpp"

namespace clr::radiosity {

struct GuideView {
  image::Image q, target;   // densities per steradian, 2·res × res, in the red channel (all three equal)
  double kl = 0;            // Σ p log(p/q) dω over the map (0 when q = p)
  double q_mass_lit = 0;    // ∫ q over the directions where p > 0
  double lit_fraction = 0;  // the share of the sphere where p > 0
};

// The point is the first surface the model learns along the camera ray through pixel (px, py) of a width × height
// image (delta bounces followed); InputError when that ray finds none.
GuideView view_guide(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& radiance, nn::Network& guide,
                     float px, float py, int width, int height, int res);

}  // namespace clr::radiosity
