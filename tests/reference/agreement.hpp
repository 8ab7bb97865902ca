#pragma once
// How a render is judged against an independent reference (issue 3): per-channel image means, and the median over
// 8×8-pixel blocks of the blocks' relative error. Block means average the noise of 64 pixels, so the median tracks
// systematic differences (a wrong BSDF, a light leak) rather than the per-pixel noise of either image.
#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <vector>

#include "image/image.hpp"

namespace clr::test {

struct Agreement {
  std::array<double, 3> mean{}, ref_mean{};
  double worst_mean_error = 0;  // max over channels of |mean − ref_mean| / ref_mean
  double median_block_error = 0;
  double mape = 0;
};

inline Agreement agreement(const image::Image& img, const image::Image& ref, int block = 8) {
  Agreement a;
  const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      a.mean[c] += img.rgb[3 * i + c] / double(n);
      a.ref_mean[c] += ref.rgb[3 * i + c] / double(n);
    }
  for (int c = 0; c < 3; ++c)
    a.worst_mean_error = std::max(a.worst_mean_error, std::abs(a.mean[c] - a.ref_mean[c]) / a.ref_mean[c]);
  std::vector<double> errors;
  for (int by = 0; by + block <= img.height; by += block)
    for (int bx = 0; bx + block <= img.width; bx += block) {
      double s = 0, r = 0;
      for (int y = by; y < by + block; ++y)
        for (int x = bx; x < bx + block; ++x)
          for (int c = 0; c < 3; ++c) {
            s += img.pixel(x, y)[c];
            r += ref.pixel(x, y)[c];
          }
      const double count = 3.0 * block * block;
      errors.push_back(std::abs(s - r) / count / (r / count + 0.01));
    }
  std::nth_element(errors.begin(), errors.begin() + std::ptrdiff_t(errors.size() / 2), errors.end());
  a.median_block_error = errors[errors.size() / 2];
  a.mape = image::compare(img, ref).mape;
  return a;
}

// A render's noise, measured from two renders with different seeds (a and b, each half the samples): the relative
// standard deviation of their average's channel means (worst channel) and the median over 8×8 blocks of the blocks'.
// Each pixel's variance comes from its own pair, E[(a − b)²] = 2 Var(a), so the estimate pools every pixel rather
// than resting on one draw of the difference of the means. Fireflies make it larger, never smaller.
struct Noise {
  double mean = 0;
  double median_block = 0;
};

inline Noise noise_of_average(const image::Image& a, const image::Image& b, const image::Image& ref) {
  Noise n;
  const double pixels = double(a.width) * a.height;
  // Var of the average's pixel, (a − b)² / 4, summed over the pixels that a mean averages.
  auto var = [&](std::size_t i) { return (double(a.rgb[i]) - b.rgb[i]) * (double(a.rgb[i]) - b.rgb[i]) / 4; };
  for (int c = 0; c < 3; ++c) {
    double v = 0, r = 0;
    for (std::size_t i = std::size_t(c); i < a.rgb.size(); i += 3) {
      v += var(i);
      r += ref.rgb[i] / pixels;
    }
    n.mean = std::max(n.mean, std::sqrt(v) / pixels / r);
  }
  std::vector<double> blocks;
  for (int by = 0; by + 8 <= a.height; by += 8)
    for (int bx = 0; bx + 8 <= a.width; bx += 8) {
      double v = 0, r = 0;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x)
          for (int c = 0; c < 3; ++c) {
            v += var((std::size_t(y) * std::size_t(a.width) + std::size_t(x)) * 3 + std::size_t(c));
            r += ref.pixel(x, y)[c] / (3 * 64);
          }
      blocks.push_back(std::sqrt(v) / (3 * 64) / (r + 0.01));
    }
  std::nth_element(blocks.begin(), blocks.begin() + std::ptrdiff_t(blocks.size() / 2), blocks.end());
  n.median_block = blocks[blocks.size() / 2];
  return n;
}

inline image::Image average(const image::Image& a, const image::Image& b) {
  image::Image m = a;
  for (std::size_t i = 0; i < m.rgb.size(); ++i) m.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
  return m;
}

inline std::ostream& operator<<(std::ostream& os, const Agreement& a) {
  return os << "means (" << a.mean[0] << ", " << a.mean[1] << ", " << a.mean[2] << ") vs reference (" << a.ref_mean[0]
            << ", " << a.ref_mean[1] << ", " << a.ref_mean[2] << "), worst channel-mean error "
            << 100 * a.worst_mean_error << " %, median 8x8-block error " << 100 * a.median_block_error << " %, MAPE "
            << 100 * a.mape << " %";
}

}  // namespace clr::test
