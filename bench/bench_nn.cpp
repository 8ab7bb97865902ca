// Network engine benchmark (DESIGN.md §6): GEMM GFLOP/s per backend beside the device's measured FMA peak and
// OpenBLAS SGEMM of the same shape; one N-Module training step beside the same step in PyTorch (bench/torch_anchor.py).
// Usage: bench_nn [--json] [--device SPEC] [--quick]
#include <cblas.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/device.hpp"
#include "nn/gemm.hpp"

using namespace clr;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

template <typename F>
double best_of(int reps, F&& f) {
  double best = 1e30;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    f();
    best = std::min(best, seconds_since(t0));
  }
  return best;
}

double fma_peak_gflops(cl::Context& ctx) {
  auto k = ctx.program({"peak.cl"}).kernel("fma_peak");
  const std::size_t items = std::max<std::size_t>(ctx.device().compute_units, 1) * 1024;
  const unsigned iters = ctx.device().type == "cpu" ? 2048 : 65536;
  cl::Buffer<float> out(ctx, items);
  k.args(iters, 0.999f, 0.001f, out);
  k.launch(items, 64);
  ctx.finish();
  const double t = best_of(3, [&] {
    k.launch(items, 64);
    ctx.finish();
  });
  return double(items) * iters * 8 * 16 * 2 / t * 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
  bool json = false, quick = false;
  std::string spec;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json"))
      json = true;
    else if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--device") && i + 1 < argc)
      spec = argv[++i];
  }
  cl::Context ctx(cl::select_device(spec));
  const double peak = fma_peak_gflops(ctx);
  if (!json) std::printf("device: %s\nFMA peak (measured): %.0f GFLOP/s\n", ctx.device().describe().c_str(), peak);

  nlohmann::json gemm_rows = nlohmann::json::array();
  const std::size_t n = 512, k = 512;
  std::vector<std::size_t> batches =
      quick ? std::vector<std::size_t>{4096} : std::vector<std::size_t>{4096, 16384, 65536};
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (std::size_t rows : batches) {
    std::vector<float> a(rows * k), w(k * n), c(rows * n);
    for (auto& x : a) x = u(rng);
    for (auto& x : w) x = u(rng);
    const double flops = 2.0 * double(rows) * double(n) * double(k);
    const double t_blas = best_of(3, [&] {
      cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, int(rows), int(n), int(k), 1.0f, a.data(), int(k),
                  w.data(), int(n), 0.0f, c.data(), int(n));
    });
    const double blas = flops / t_blas * 1e-9;
    cl::Buffer<float> da(ctx, std::span<const float>(a)), dw(ctx, std::span<const float>(w)), dc(ctx, rows * n);
    for (auto choice : {nn::GemmChoice::Own, nn::GemmChoice::CLBlast}) {
      if (choice == nn::GemmChoice::CLBlast && quick) continue;
      nn::Gemm g(ctx, choice);
      auto run = [&] {
        g.run(nn::Op::N, nn::Op::N, rows, n, k, 1.0f, nn::mat(da, k), nn::mat(dw, n), 0.0f, nn::mat(dc, n));
        ctx.finish();
      };
      run();
      const double gf = flops / best_of(choice == nn::GemmChoice::CLBlast ? 2 : 3, run) * 1e-9;
      // A figure for a wrong product is worthless: check it against OpenBLAS's.
      const auto got = dc.read();
      double err = 0, scale = 0;
      for (std::size_t i = 0; i < got.size(); ++i) {
        err = std::max(err, double(std::abs(got[i] - c[i])));
        scale = std::max(scale, double(std::abs(c[i])));
      }
      if (err > 1e-4 * scale) {
        std::fprintf(stderr, "bench_nn: %s GEMM differs from OpenBLAS by %g (max |C| %g)\n",
                     nn::to_string(g.backend()).c_str(), err, scale);
        return 1;
      }
      gemm_rows.push_back({{"backend", nn::to_string(g.backend())},
                           {"rows", rows},
                           {"gflops", gf},
                           {"openblas_gflops", blas},
                           {"peak_gflops", peak}});
      if (!json)
        std::printf(
            "GEMM (%zux512)·(512x512) %-8s %7.1f GFLOP/s  (%.0f%% of FMA peak; OpenBLAS %.1f GFLOP/s, ratio %.2f)\n",
            rows, nn::to_string(g.backend()).c_str(), gf, 100 * gf / peak, blas, gf / blas);
    }
  }
  if (json) std::cout << nlohmann::json{{"gemm", gemm_rows}}.dump() << "\n";
  return 0;
}
