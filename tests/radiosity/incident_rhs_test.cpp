// kernels/radiosity.cl:incident_rhs against a double-precision host twin.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "cl/buffer.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

TEST_F(ClTest, IncidentRhsMatchesDoubleTwin) {
  const unsigned M = 1037, N = 5;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  std::vector<float> weight(M * N * 3), emitted(M * N * 3), pdf(M * N);
  std::vector<int> lookup(M * N);
  std::vector<float> radiance;
  for (auto& v : weight) v = u(rng);
  for (auto& v : emitted) v = u(rng) < 0.3f ? u(rng) : 0.0f;
  for (auto& v : pdf) v = 0.05f + u(rng);
  int rows = 0;
  for (auto& l : lookup) l = u(rng) < 1.4f ? rows++ : -1;  // 70 % of samples hit a surface the network evaluates
  radiance.resize(std::size_t(rows) * 3);
  for (auto& v : radiance) v = u(rng);
  weight[7 * 3 + 1] = std::numeric_limits<float>::infinity();
  lookup[7] = 0;  // sample 7 (of point 1) uses the infinite weight: dropped and counted

  std::vector<double> twin(M * 3, 0.0);
  for (unsigned m = 0; m < M; ++m)
    for (unsigned n = 0; n < N; ++n) {
      const std::size_t s = m * N + n;
      if (s == 7) continue;
      for (int c = 0; c < 3; ++c) {
        double term = emitted[s * 3 + c];
        if (lookup[s] >= 0) term += double(weight[s * 3 + c]) * radiance[std::size_t(lookup[s]) * 3 + c];
        twin[m * 3 + c] += term / pdf[s] / N;
      }
    }

  cl::Buffer<float> w(ctx(), std::span<const float>(weight)), e(ctx(), std::span<const float>(emitted)),
      r(ctx(), std::span<const float>(radiance)), p(ctx(), std::span<const float>(pdf));
  cl::Buffer<int> l(ctx(), std::span<const int>(lookup));
  auto out_host = with_canaries(M * 3);
  cl::Buffer<float> out(ctx(), std::span<const float>(out_host));
  cl::Buffer<unsigned> bad(ctx(), 1);
  bad.fill(0u);
  ctx().program({"radiosity.cl"}).kernel("incident_rhs").args(w, e, p, l, r, M, N, out, bad).launch(M);
  out.read(out_host);
  EXPECT_TRUE(canaries_intact(out_host, M * 3));
  EXPECT_TRUE(all_near(std::span<const float>(out_host.data(), M * 3), std::span<const double>(twin)));
  EXPECT_EQ(bad.read()[0], 1u);
}

}  // namespace
}  // namespace clr::test
