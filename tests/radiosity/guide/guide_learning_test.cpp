// The I-Module learns: with a fixed target — a small bright emitter seen from one point, black elsewhere — the KL
// and IKL gradients train the real I-Module network (hash grid, SH, 3 × 64 MLP, Adam) until its lobes hold most of
// their mass in the emitter's cone, which covers 1.7 % of the sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/pcg32.hpp"
#include "nn/network.hpp"
#include "radiosity/guide/i_module.hpp"
#include "radiosity/guide/vmf_mixture.hpp"
#include "scene/frame.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

double cone_share_after_training(cl::Context& ctx, bool improved, int steps) {
  constexpr std::size_t M = 256, N = 8;
  const glm::vec3 emitter = glm::normalize(glm::vec3(1.0f, 0.5f, 0.6f));
  const float cone_cos = std::cos(15.0f * float(M_PI) / 180.0f);
  const float c = 0.5f, uniform_pdf = float(1.0 / (4.0 * M_PI));

  nn::Network net(ctx, radiosity::i_module_config({0, 0, 0}, {1, 1, 1}));
  radiosity::VmfMixture vmf(ctx);
  // Every point is the same surface point seen from above (raw row: x, ω_o, n, albedo, roughness).
  std::vector<float> rows;
  for (std::size_t m = 0; m < M; ++m)
    rows.insert(rows.end(), {0.5f, 0.5f, 0.5f, 0, 0, 1, 0, 0, 1, 0.5f, 0.5f, 0.5f, 1.0f});
  cl::Buffer<float> raw_rows(ctx, std::span<const float>(rows));
  std::vector<float> up(M * 3, 0.0f);
  for (std::size_t m = 0; m < M; ++m) up[3 * m + 2] = 1.0f;
  cl::Buffer<float> normals(ctx, std::span<const float>(up));
  cl::Buffer<float> u_dev(ctx, M * N * 3), guided(ctx, M * N * 3), dirs_dev(ctx, M * N * 3), bsdf_pdf(ctx, M * N),
      pdf(ctx, M * N), q(ctx, M * N), weight(ctx, M * N * 3), emitted_dev(ctx, M * N * 3), radiance(ctx, 3),
      d_raw(ctx, M * 32);
  cl::Buffer<int> lookup(ctx, M * N);
  // F = ∫ t dω: the cone's solid angle (t = 1 inside it).
  cl::Buffer<float> scattered(ctx, M * 3);
  scattered.fill(float(2 * M_PI * (1 - double(cone_cos))));
  weight.fill(0.0f);
  radiance.fill(0.0f);
  lookup.fill(-1);
  bsdf_pdf.fill(uniform_pdf);
  Pcg32 rng(0, 99);
  std::vector<float> u(M * N * 3), dirs(M * N * 3), emitted(M * N * 3);
  nn::NetworkContext fwd;
  // The lobes at the points (activations kept) and a direction from them for every sample.
  const auto draw_from_q = [&] {
    net.forward_train(raw_rows, M, fwd);
    vmf.decode(fwd.output(), normals, M);
    for (auto& x : u) x = rng.next_float();
    u_dev.write(u);
    vmf.sample(u_dev, N, guided);
    return guided.read();
  };
  for (int step = 0; step < steps; ++step) {
    const auto from_q = draw_from_q();
    // The one-sample mixture of a uniform "BSDF" and q.
    for (std::size_t s = 0; s < M * N; ++s) {
      glm::vec3 w(from_q[3 * s], from_q[3 * s + 1], from_q[3 * s + 2]);
      if (rng.next_float() < c) w = scene::sample_uniform_sphere({rng.next_float(), rng.next_float()});
      const float t = glm::dot(w, emitter) > cone_cos ? 1.0f : 0.0f;
      for (int i = 0; i < 3; ++i) {
        dirs[3 * s + std::size_t(i)] = w[i];
        emitted[3 * s + std::size_t(i)] = t;
      }
    }
    dirs_dev.write(dirs);
    emitted_dev.write(emitted);
    vmf.mixture_pdf(dirs_dev, bsdf_pdf, N, c, pdf, q);
    vmf.loss({dirs_dev, bsdf_pdf, pdf, weight, emitted_dev, lookup, radiance, scattered}, N, improved, d_raw);
    net.backward(fwd, d_raw);
    net.adam_step();
  }
  // The learned mixture's mass in the cone, by sampling it.
  const auto from_q = draw_from_q();
  std::size_t inside = 0;
  for (std::size_t s = 0; s < M * N; ++s)
    inside += glm::dot(glm::vec3(from_q[3 * s], from_q[3 * s + 1], from_q[3 * s + 2]), emitter) > cone_cos;
  return double(inside) / double(M * N);
}

TEST_F(ClTest, GuideLearnsASmallEmittersCone) {
  for (const bool improved : {false, true}) {
    const double share = cone_share_after_training(ctx(), improved, 300);
    std::printf("[ measured ] %s: %.1f %% of q's samples in the emitter's cone (1.7 %% of the sphere)\n",
                improved ? "IKL" : "KL", 100 * share);
    EXPECT_GT(share, 0.6) << (improved ? "IKL" : "KL");
  }
}

}  // namespace
}  // namespace clr::test
