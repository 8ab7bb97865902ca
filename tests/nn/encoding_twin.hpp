#pragma once
// Double-precision host twins of the hash-grid and SH encodings. The grid twin locates the cell with the same float
// operations as the kernel (so both pick the same cell for a point near a cell boundary) and interpolates in double.
#include <cmath>
#include <cstdint>
#include <vector>

#include "nn/hashgrid.hpp"

namespace clr::test {

struct GridCorner {
  std::size_t entry;  // table entry (row of F floats)
  double weight;
};

inline std::vector<GridCorner> grid_corners(const nn::HashGridConfig& cfg, const nn::HashGridLevel& lv,
                                            const float* p) {
  float t[3];
  std::uint32_t c[3];
  for (int i = 0; i < 3; ++i) {
    const float inv = 1.0f / (cfg.bbox_hi[i] - cfg.bbox_lo[i]);
    const float x = std::min(std::max((p[i] - cfg.bbox_lo[i]) * inv, 0.0f), 1.0f);
    const float pos = x * float(lv.resolution);
    const float cell = std::min(std::floor(pos), float(lv.resolution) - 1.0f);
    c[i] = std::uint32_t(cell);
    t[i] = pos - cell;
  }
  std::vector<GridCorner> out;
  for (std::uint32_t k = 0; k < 8; ++k) {
    const std::uint32_t v[3] = {c[0] + (k & 1), c[1] + ((k >> 1) & 1), c[2] + (k >> 2)};
    double w = 1;
    for (int i = 0; i < 3; ++i) w *= ((k >> i) & 1) ? double(t[i]) : 1.0 - double(t[i]);
    std::uint32_t idx;
    if (lv.dense) {
      const std::uint32_t side = lv.resolution + 1;
      idx = v[0] + side * (v[1] + side * v[2]);
    } else {
      idx = (v[0] ^ (v[1] * 2654435761u) ^ (v[2] * 805459861u)) & (lv.entries - 1);
    }
    out.push_back({lv.offset + idx, w});
  }
  return out;
}

// Encoded features [levels · F] of one position.
inline std::vector<double> grid_encode(const nn::HashGridConfig& cfg, const std::vector<nn::HashGridLevel>& levels,
                                       const std::vector<double>& table, const float* p) {
  const std::size_t F = cfg.features;
  std::vector<double> out(levels.size() * F, 0.0);
  for (std::size_t l = 0; l < levels.size(); ++l)
    for (const auto& c : grid_corners(cfg, levels[l], p))
      for (std::size_t f = 0; f < F; ++f) out[l * F + f] += c.weight * table[c.entry * F + f];
  return out;
}

inline std::vector<double> sh16(double x, double y, double z) {
  const double xy = x * y, xz = x * z, yz = y * z, x2 = x * x, y2 = y * y, z2 = z * z;
  return {0.28209479177387814,
          -0.48860251190291987 * y,
          0.48860251190291987 * z,
          -0.48860251190291987 * x,
          1.0925484305920792 * xy,
          -1.0925484305920792 * yz,
          0.94617469575755997 * z2 - 0.31539156525251999,
          -1.0925484305920792 * xz,
          0.54627421529603959 * (x2 - y2),
          0.59004358992664352 * y * (-3.0 * x2 + y2),
          2.8906114426405538 * xy * z,
          0.45704579946446572 * y * (1.0 - 5.0 * z2),
          0.3731763325901154 * z * (5.0 * z2 - 3.0),
          0.45704579946446572 * x * (1.0 - 5.0 * z2),
          1.4453057213202769 * z * (x2 - y2),
          0.59004358992664352 * x * (-x2 + 3.0 * y2)};
}

}  // namespace clr::test
