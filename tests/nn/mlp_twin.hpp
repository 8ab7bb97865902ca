#pragma once
// Double-precision host twin of nn::Mlp over the same parameter layout (W_l [fan_in × fan_out], then b_l).
#include <cmath>
#include <vector>

#include "nn/mlp.hpp"

namespace clr::test {

struct MlpTwin {
  nn::MlpConfig cfg;
  std::vector<double> p;  // parameters, same layout as the device buffer

  std::size_t fan_in(std::size_t l) const { return l == 0 ? cfg.inputs : cfg.width; }
  std::size_t fan_out(std::size_t l) const { return l == cfg.hidden_layers ? cfg.outputs : cfg.width; }
  std::size_t offset(std::size_t l) const {
    std::size_t o = 0;
    for (std::size_t i = 0; i < l; ++i) o += fan_in(i) * fan_out(i) + fan_out(i);
    return o;
  }

  // One row: x [inputs] → output [outputs].
  std::vector<double> forward_row(const double* x) const {
    std::vector<double> a(x, x + cfg.inputs);
    for (std::size_t l = 0; l <= cfg.hidden_layers; ++l) {
      const std::size_t fi = fan_in(l), fo = fan_out(l), o = offset(l);
      std::vector<double> z(fo);
      for (std::size_t j = 0; j < fo; ++j) {
        double s = p[o + fi * fo + j];
        for (std::size_t i = 0; i < fi; ++i) s += a[i] * p[o + i * fo + j];
        const bool hidden = l < cfg.hidden_layers;
        z[j] = hidden ? std::max(s, 0.0) : (cfg.output_activation == nn::OutputActivation::Abs ? std::abs(s) : s);
      }
      a = std::move(z);
    }
    return a;
  }

  // L = Σ_rows Σ_j w[r, j] · out[r, j] for inputs x [rows × inputs].
  double weighted_sum(const std::vector<double>& x, const std::vector<double>& w, std::size_t rows) const {
    double L = 0;
    for (std::size_t r = 0; r < rows; ++r) {
      const auto out = forward_row(&x[r * cfg.inputs]);
      for (std::size_t j = 0; j < cfg.outputs; ++j) L += w[r * cfg.outputs + j] * out[j];
    }
    return L;
  }
};

}  // namespace clr::test
