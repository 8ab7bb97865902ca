#pragma once
// The corpus peer's judgement over independently seeded renders (issue 50 item 5): each renderer renders the scene
// with `seeds` seeds, and the seeds' spread gives the standard error of each side's channel means and 8×8-block
// means. A channel mean agrees when ours / peer − 1 lies within a small systematic allowance plus k standard errors
// of that ratio (around a scene's known, documented difference where it has one); the median block error agrees
// within its own allowance plus k times the median block's standard error. Where a scene's noise at the base spp
// would put the mean bound above the target (so that a 0.5 % bias could pass), the spp is raised rather than the
// bound (run_peer). Separate from Mitsuba itself, so that a fast test can show the judgement's power on synthetic
// renders (peer_judgement_test.cpp).
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <ostream>
#include <span>
#include <string_view>
#include <vector>

#include "image/image.hpp"

namespace clr::test {

struct PeerPlan {
  int seeds = 10;
  int base_spp = 32, max_spp = 8192;  // per seed: the pilot's, and the cap on raising it
  // The judged renders' processor time, both sides, as the pilot's scales to them: a cap on the spp as well, which
  // lets cheap scenes rise further than costly ones. Processor time rather than the clock's, so that the spp chosen
  // does not depend on what else the machine runs.
  double final_seconds = 120;
  // A mean agrees within mean_allowance + mean_k σ; the spp is raised until that is at most target_bound, so that a
  // 0.5 % bias fails with ≥ 93 % probability (0.5 % lies 1.5 σ beyond the bound at the target).
  double mean_allowance = 0.002, mean_k = 3, target_bound = 0.004;
  double block_allowance = 0.01, block_k = 3;
};

// One renderer's seeds: each channel's image mean and each 8×8 block's mean (over its pixels and channels), averaged
// over the seeds, with the standard errors of those averages from the seeds' spread.
struct SeedStats {
  std::array<double, 3> mean{}, mean_se{};
  std::vector<double> block, block_se;
};

namespace detail {
// Mean and standard error of the mean of samples[i][k] over i, for every k.
inline void mean_and_se(const std::vector<std::vector<double>>& samples, std::vector<double>& mean,
                        std::vector<double>& se) {
  const std::size_t n = samples.size(), m = samples.front().size();
  mean.assign(m, 0);
  se.assign(m, 0);
  for (const auto& s : samples)
    for (std::size_t k = 0; k < m; ++k) mean[k] += s[k] / double(n);
  for (const auto& s : samples)
    for (std::size_t k = 0; k < m; ++k) se[k] += (s[k] - mean[k]) * (s[k] - mean[k]);
  for (double& v : se) v = std::sqrt(v / double(n - 1) / double(n));
}

inline double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}
}  // namespace detail

inline SeedStats seed_stats(const std::vector<image::Image>& seeds) {
  std::vector<std::vector<double>> means, blocks;
  for (const image::Image& img : seeds) {
    std::vector<double> m(3, 0.0), b;
    const double pixels = double(img.width) * img.height;
    for (std::size_t i = 0; i < img.rgb.size(); ++i) m[i % 3] += img.rgb[i] / pixels;
    for (int by = 0; by + 8 <= img.height; by += 8)
      for (int bx = 0; bx + 8 <= img.width; bx += 8) {
        double s = 0;
        for (int y = by; y < by + 8; ++y)
          for (int x = bx; x < bx + 8; ++x)
            for (int c = 0; c < 3; ++c) s += img.pixel(x, y)[c];
        b.push_back(s / (3 * 64));
      }
    means.push_back(std::move(m));
    blocks.push_back(std::move(b));
  }
  SeedStats st;
  std::vector<double> mean, se;
  detail::mean_and_se(means, mean, se);
  std::copy(mean.begin(), mean.end(), st.mean.begin());
  std::copy(se.begin(), se.end(), st.mean_se.begin());
  detail::mean_and_se(blocks, st.block, st.block_se);
  return st;
}

struct SeedVerdict {
  int seeds = 0, spp = 0;            // spp per seed
  std::array<double, 3> expected{};  // the scene's known difference per channel, ours / peer − 1: the bounds' centre
  std::array<double, 3> ours{}, peer{};
  std::array<double, 3> ratio{};                             // ours / peer − 1 of each channel mean
  std::array<double, 3> sigma{};                             // the standard error of that ratio
  std::array<double, 3> sigma_ours{}, sigma_peer{};          // its two parts: each side's relative standard error
  std::array<double, 3> bound{};                             // allowance + k σ
  double block_error = 0, block_sigma = 0, block_bound = 0;  // medians over the 8×8 blocks

  // The channel furthest from its expectation, measured in its bound.
  int worst() const {
    int w = 0;
    for (int c = 1; c < 3; ++c)
      if (std::abs(ratio[c] - expected[c]) / bound[c] > std::abs(ratio[w] - expected[w]) / bound[w]) w = c;
    return w;
  }
  bool means_agree() const {
    for (int c = 0; c < 3; ++c)
      if (!(std::abs(ratio[c] - expected[c]) <= bound[c])) return false;
    return true;
  }
  bool blocks_agree() const { return block_error <= block_bound; }
  bool agrees() const { return means_agree() && blocks_agree(); }
  double widest_bound() const { return *std::max_element(bound.begin(), bound.end()); }
};

// A difference between the two renderers that is understood and documented (docs/scenes.md): the scene's channel
// means are judged around `expected` (ours / peer − 1 per channel, as measured) with the same bound as any other
// scene, so that a further 0.5 % still fails.
struct KnownDifference {
  std::string_view scene;
  std::array<double, 3> expected;
  std::string_view reason;
};
inline const KnownDifference* known_difference(std::span<const KnownDifference> known, std::string_view scene) {
  for (const auto& k : known)
    if (k.scene == scene) return &k;
  return nullptr;
}

inline SeedVerdict judge_seeds(const std::vector<image::Image>& ours, const std::vector<image::Image>& peer,
                               const PeerPlan& plan, const std::array<double, 3>& expected = {}) {
  const SeedStats o = seed_stats(ours), p = seed_stats(peer);
  SeedVerdict v;
  v.seeds = int(ours.size());
  v.expected = expected;
  for (int c = 0; c < 3; ++c) {
    v.ours[c] = o.mean[c];
    v.peer[c] = p.mean[c];
    v.ratio[c] = o.mean[c] / p.mean[c] - 1;
    // First-order error of a ratio of independent means.
    v.sigma_ours[c] = o.mean_se[c] / p.mean[c];
    v.sigma_peer[c] = o.mean[c] * p.mean_se[c] / (p.mean[c] * p.mean[c]);
    v.sigma[c] = std::hypot(v.sigma_ours[c], v.sigma_peer[c]);
    v.bound[c] = plan.mean_allowance + plan.mean_k * v.sigma[c];
  }
  // Relative block errors with a floor of 0.01 in the denominator, so that black blocks do not dominate.
  std::vector<double> errors, sigmas;
  for (std::size_t k = 0; k < p.block.size(); ++k) {
    const double scale = p.block[k] + 0.01;
    errors.push_back(std::abs(o.block[k] - p.block[k]) / scale);
    sigmas.push_back(std::hypot(o.block_se[k], p.block_se[k]) / scale);
  }
  v.block_error = detail::median(errors);
  v.block_sigma = detail::median(sigmas);
  v.block_bound = plan.block_allowance + plan.block_k * v.block_sigma;
  return v;
}

// The spp per seed at which the widest mean bound is expected to be at most the target: the noise falls as 1/√spp,
// so the pilot's spp doubles until it does, up to the cap and while the renders' processor time (the pilot's,
// pilot_seconds, scaled by the spp) stays within the plan's.
inline int spp_for_target(const SeedVerdict& pilot, double pilot_seconds, const PeerPlan& plan) {
  const double sigma = *std::max_element(pilot.sigma.begin(), pilot.sigma.end());
  const double wanted = (plan.target_bound - plan.mean_allowance) / plan.mean_k;
  int spp = pilot.spp;
  while (spp < plan.max_spp && sigma * std::sqrt(double(pilot.spp) / spp) > wanted &&
         pilot_seconds * 2 * spp / pilot.spp <= plan.final_seconds)
    spp *= 2;
  return spp;
}

// User and system time of this process and of the children it has waited for (a peer renderer run as a command).
inline double processor_seconds() {
  double s = 0;
  for (const int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage u{};
    getrusage(who, &u);
    s += double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }
  return s;
}

// `seeds` renders at `spp` per seed, seeded first_seed, first_seed + 1, ...
using SeededRender = std::function<std::vector<image::Image>(int spp, int first_seed, int seeds)>;

// A pilot at the base spp; where its bound is above the target, the judgement is made on fresh seeds at the spp
// chosen from it (the pilot's own noise estimate chose that spp, so judging it again would favour low estimates).
inline SeedVerdict run_peer(const SeededRender& ours, const SeededRender& peer, const PeerPlan& plan,
                            const std::array<double, 3>& expected = {}) {
  const double start = processor_seconds();
  SeedVerdict v = judge_seeds(ours(plan.base_spp, 1, plan.seeds), peer(plan.base_spp, 1, plan.seeds), plan, expected);
  v.spp = plan.base_spp;
  if (v.widest_bound() <= plan.target_bound) return v;
  const int spp = spp_for_target(v, processor_seconds() - start, plan);
  if (spp == plan.base_spp) return v;
  v = judge_seeds(ours(spp, 1 + plan.seeds, plan.seeds), peer(spp, 1 + plan.seeds, plan.seeds), plan, expected);
  v.spp = spp;
  return v;
}

inline std::ostream& operator<<(std::ostream& os, const SeedVerdict& v) {
  const int w = v.worst();
  os << v.seeds << " seeds x " << v.spp << " spp; channel means ours / peer: " << 1 + v.ratio[0] << ", "
     << 1 + v.ratio[1] << ", " << 1 + v.ratio[2] << " (sigma " << 100 * v.sigma[0] << ", " << 100 * v.sigma[1] << ", "
     << 100 * v.sigma[2] << " %); worst channel "
     << "RGB"[w] << ": " << 100 * v.ratio[w] << " % (sigma ours " << 100 * v.sigma_ours[w] << " %, peer's "
     << 100 * v.sigma_peer[w] << " %)";
  if (v.expected != std::array<double, 3>{}) os << " against the expected " << 100 * v.expected[w] << " %";
  return os << ", bound " << 100 * v.bound[w] << " %; median 8x8 block " << 100 * v.block_error << " % (sigma "
            << 100 * v.block_sigma << " %), bound " << 100 * v.block_bound << " %";
}

}  // namespace clr::test
