// Network engine benchmark (docs/design.md §6): GEMM GFLOP/s per backend beside the device's measured FMA peak and
// OpenBLAS SGEMM of the same shape; one N-Module training step beside the same step in PyTorch (bench/torch_anchor.py).
// Usage: bench_nn [--json] [--device SPEC] [--quick | --acceptance]
// --acceptance: only the GPU-pace figures (bench/gpu_acceptance.sh's summary): the engine's GEMM (the probe's pick) at
// (4096 and 16384 × 512)·(512 × 512) and the weight gradient (512 × 16384)·(16384 × 512), and N-Module steps at
// B = 4096 and 16384, each beside its target.
#include <cblas.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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
#include "nn/loss.hpp"
#include "nn/mlp.hpp"
#include "nn/network.hpp"

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

// The device's FMA ceiling, measured: the best of several vector widths × independent chains per work-item, with
// every compute unit busy. No single shape reaches the limit everywhere: a width wider than the registers splits
// and spills (float16 on AVX2), too few chains leave the FMA pipes waiting on latency (4 cycles × 2 pipes needs ≥ 8
// in flight), and PoCL's work-group vectoriser may widen scalar code itself — then VW = 1 is the fastest.
struct Peak {
  double gflops = 0;
  unsigned vw = 0, chains = 0;
};

Peak fma_peak(cl::Context& ctx) {
  const std::size_t items = std::max<std::size_t>(ctx.device().compute_units, 1) * 1024;
  const bool cpu = ctx.device().type == cl::DeviceType::Cpu;
  cl::Buffer<float> out(ctx, items);
  Peak best;
  for (unsigned vw : {1u, 2u, 4u, 8u, 16u})
    for (unsigned chains : {8u, 12u, 16u, 24u}) {
      // About the same flops per launch whatever the shape (≈ 0.1 s on a 2-core CPU).
      const unsigned iters = std::max(16u, (cpu ? 2048u * 12 * 16 : 65536u * 12 * 16) / (chains * vw));
      auto k = ctx.program({"peak.cl"}, "-DVW=" + std::to_string(vw) + " -DCHAINS=" + std::to_string(chains))
                   .kernel("fma_peak");
      k.args(iters, 0.999f, 0.001f, out);
      k.launch(items, 64);
      ctx.finish();
      const double t = best_of(3, [&] {
        k.launch(items, 64);
        ctx.finish();
      });
      const double gflops = double(items) * iters * chains * vw * 2 / t * 1e-9;
      if (gflops > best.gflops) best = {gflops, vw, chains};
    }
  return best;
}

// The cross-check: compute units × reported clock × native float width × 2 flops an FMA × 2 FMA pipes (x86 cores
// since Haswell and Zen; GPUs report compute units, not the lanes in them, so there is no figure for them).
// The reported clock is the base clock: a measured peak above this figure means the cores ran faster (turbo).
double nominal_cpu_peak_gflops(const cl::DeviceInfo& d) {
  if (d.type != cl::DeviceType::Cpu) return 0;
  cl_uint mhz = 0, width = 0;
  clGetDeviceInfo(d.device, CL_DEVICE_MAX_CLOCK_FREQUENCY, sizeof mhz, &mhz, nullptr);
  clGetDeviceInfo(d.device, CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT, sizeof width, &width, nullptr);
  return double(d.compute_units) * mhz * 1e-3 * width * 2 * 2;
}

std::vector<float> random_raw(std::size_t rows, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> n01;
  std::vector<float> raw(rows * nn::kRawInputs);
  for (std::size_t r = 0; r < rows; ++r) {
    float* row = &raw[r * nn::kRawInputs];
    for (std::size_t c = 0; c < nn::kRawInputs; ++c) row[c] = u(rng);
    for (std::size_t s : {nn::raw::kDirection, nn::raw::kNormal}) {
      float v[3] = {n01(rng), n01(rng), n01(rng)};
      const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (int i = 0; i < 3; ++i) row[s + i] = v[i] / len;
    }
  }
  return raw;
}

// The PyTorch anchor's step time in ms, or a negative value when python3 + torch are not available.
double torch_anchor_ms(std::size_t batch) {
  const std::string script = std::string(CLR_SOURCE_DIR) + "/bench/torch_anchor.py";
  for (const char* py : {"python3", "/usr/bin/python3"}) {
    if (std::system((std::string(py) + " -c 'import torch' >/dev/null 2>&1").c_str()) != 0) continue;
    const std::string cmd = std::string(py) + " " + script + " --batch " + std::to_string(batch);
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) continue;
    std::string out;
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    if (pclose(p) != 0) continue;
    try {
      return nlohmann::json::parse(out).at("step_ms").get<double>();
    } catch (const std::exception&) {
      continue;
    }
  }
  return -1.0;
}

// One N-Module training step (docs/design.md §2): forward of B points, inference of N·B incident points, relative L2
// loss, backward, Adam over the MLP and the touched hash-grid entries; the median of `reps`, each stage timed to
// completion.
struct StepTime {
  double ms = 0, fwd_ms = 0, inf_ms = 0, bwd_ms = 0, adam_ms = 0, peak_mib = 0;
  int reps = 0;
  std::size_t levels = 0, features = 0, log2_table = 0, parameters = 0;
  std::string plan;
};

StepTime nmodule_step(cl::Context& ctx, std::size_t B, int reps, std::mt19937& rng) {
  constexpr std::size_t N = 4;
  auto cfg = nn::n_module_config({0, 0, 0}, {1, 1, 1});
  cfg.gemm = nn::GemmChoice::Auto;
  nn::Network net(ctx, cfg);
  const auto raw = random_raw(B, rng), incident = random_raw(N * B, rng);
  std::vector<float> target(B * 3);
  for (auto& t : target) t = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
  cl::Buffer<float> draw(ctx, std::span<const float>(raw)), dinc(ctx, std::span<const float>(incident)),
      dt(ctx, std::span<const float>(target)), grad(ctx, B * 3), li(ctx, N * B * 3);
  nn::Loss loss(ctx);
  nn::NetworkContext c;
  double t_fwd = 0, t_inf = 0, t_bwd = 0, t_adam = 0;
  auto step = [&](bool timed) {
    auto t0 = Clock::now();
    net.forward_train(draw, B, c);
    ctx.finish();
    if (timed) t_fwd += seconds_since(t0);
    t0 = Clock::now();
    net.infer(dinc, N * B, li);
    ctx.finish();
    if (timed) t_inf += seconds_since(t0);
    t0 = Clock::now();
    loss.evaluate(c.output(), dt, B * 3, 1.0f / float(B * 3), 1.0f, grad);
    net.backward(c, grad);
    ctx.finish();
    if (timed) t_bwd += seconds_since(t0);
    t0 = Clock::now();
    net.adam_step();
    ctx.finish();
    if (timed) t_adam += seconds_since(t0);
  };
  step(false);
  step(false);
  ctx.reset_peak();
  std::vector<double> times;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    step(true);
    times.push_back(seconds_since(t0));
  }
  std::sort(times.begin(), times.end());
  StepTime st;
  st.ms = 1000 * times[times.size() / 2];
  st.reps = reps;
  st.fwd_ms = 1000 * t_fwd / reps;
  st.inf_ms = 1000 * t_inf / reps;
  st.bwd_ms = 1000 * t_bwd / reps;
  st.adam_ms = 1000 * t_adam / reps;
  st.peak_mib = double(ctx.peak_bytes()) / (1024.0 * 1024.0);
  st.parameters = net.parameter_count();
  st.levels = cfg.encoder.grid->levels;
  st.features = cfg.encoder.grid->features;
  st.log2_table = cfg.encoder.grid->log2_table;
  st.plan = nn::to_string(net.gemm().plan());
  return st;
}

// The figures of the GPU-pace targets (docs/nvidia.md), each beside its target: the engine's GEMM plan (the one
// training uses) at the N-Module's forward products and its weight gradient, and whole N-Module steps.
int run_acceptance(cl::Context& ctx, double peak_gflops, bool json) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  nn::Gemm engine(ctx, nn::GemmChoice::Auto);
  const auto random = [&](std::size_t count) {
    std::vector<float> v(count);
    for (auto& x : v) x = u(rng);
    return cl::Buffer<float>(ctx, std::span<const float>(v));
  };
  constexpr std::size_t W = 512;
  const auto tflops = [&](nn::Op op_a, std::size_t m, std::size_t n, std::size_t k, const cl::Buffer<float>& a,
                          std::size_t lda, const cl::Buffer<float>& b, cl::Buffer<float>& c) {
    const auto run = [&] {
      engine.run(op_a, nn::Op::N, m, n, k, 1.0f, nn::mat(a, lda), nn::mat(b, n), 0.0f, nn::mat(c, n));
      ctx.finish();
    };
    run();
    return 2.0 * double(m) * double(n) * double(k) / best_of(5, run) * 1e-12;
  };
  nlohmann::json figures = {{"device", ctx.device().describe()},
                            {"driver", ctx.device().driver_version},
                            {"gemm_plan", nn::to_string(engine.plan())},
                            {"fma_peak_tflops", peak_gflops * 1e-3}};
  const double peak_t = peak_gflops * 1e-3;
  for (const std::size_t rows : {std::size_t(4096), std::size_t(16384)}) {
    const auto a = random(rows * W), w = random(W * W);
    cl::Buffer<float> c(ctx, rows * W);
    const double t = tflops(nn::Op::N, rows, W, W, a, W, w, c);
    figures["gemm_tflops_" + std::to_string(rows)] = t;
    if (!json)
      std::printf(
          "engine GEMM %s (%zux512)·(512x512): %.2f TFLOP/s, %.0f %% of the FMA peak (target on an H100/H200: >= %s)\n",
          nn::to_string(engine.plan()).c_str(), rows, t, 100 * t / peak_t, rows == 4096 ? "30" : "40");
  }
  {
    constexpr std::size_t K = 16384;  // the weight gradient of a 512-wide layer over the GPU's batch
    const auto x = random(K * W), dy = random(K * W);
    cl::Buffer<float> dw(ctx, W * W);
    const double t = tflops(nn::Op::T, W, W, K, x, W, dy, dw);
    figures["gemm_tflops_dw"] = t;
    if (!json)
      std::printf(
          "engine GEMM %s dW (512x16384)·(16384x512): %.2f TFLOP/s, %.0f %% of the FMA peak (target on an H100/H200: "
          ">= 30)\n",
          nn::to_string(engine.plan()).c_str(), t, 100 * t / peak_t);
  }
  for (const std::size_t B : {std::size_t(4096), std::size_t(16384)}) {
    const StepTime st = nmodule_step(ctx, B, 5, rng);
    figures["nmodule_step_ms_" + std::to_string(B)] = st.ms;
    if (!json)
      std::printf(
          "N-Module step B=%zu x 4, width 512: %.2f ms (forward %.2f, inference %.2f, loss+backward %.2f, adam %.2f; "
          "target on an H100/H200: <= %s ms)\n",
          B, st.ms, st.fwd_ms, st.inf_ms, st.bwd_ms, st.adam_ms, B == 4096 ? "1.5" : "4.5");
  }
  if (json) std::cout << figures.dump() << "\n";
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  bool json = false, quick = false, acceptance = false;
  std::string spec;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json"))
      json = true;
    else if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--acceptance"))
      acceptance = true;
    else if (!std::strcmp(argv[i], "--device") && i + 1 < argc)
      spec = argv[++i];
  }
  cl::Context ctx(cl::select_device(spec));
  const Peak fma = fma_peak(ctx);
  bool above_peak = false;
  const double peak = fma.gflops;
  if (!json) {
    std::printf("device: %s\nFMA peak (measured): %.0f GFLOP/s (float%u × %u chains a work-item)",
                ctx.device().describe().c_str(), peak, fma.vw, fma.chains);
    if (const double nominal = nominal_cpu_peak_gflops(ctx.device()); nominal > 0)
      std::printf("; nominal at the reported clock: %.0f GFLOP/s", nominal);
    std::printf("\n");
    // The anchor's own kernel: OPENBLAS_CORETYPE can pin an older one (an AVX2 kernel on an AVX-512 machine).
    std::printf("OpenBLAS anchor: %s kernel, %d threads\n", openblas_get_corename(), openblas_get_num_threads());
  }

  if (acceptance) return run_acceptance(ctx, peak, json);

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
    // The probe's pick among our kernels, then every local-memory tiled block and a register tile beside it (one
    // of them is the pick), then CLBlast: each backend's figure against the same peak.
    std::vector<nn::GemmPlan> plans = {nn::choose_gemm_plan(ctx, nn::GemmChoice::Own)};
    const nn::GemmTile tile = nn::gemm_tiles(ctx.device()).front();
    if (plans.front().backend != nn::GemmBackend::Own) plans.push_back({nn::GemmBackend::Own, tile});
    // A CPU has no tiled candidates (the probe skips them there); its figure is printed all the same.
    cl::DeviceInfo gpu = ctx.device();
    gpu.type = cl::DeviceType::Gpu;
    auto blocks = nn::gemm_blocks(ctx.device());
    if (blocks.empty()) blocks = {nn::gemm_blocks(gpu).front()};
    for (const auto& b : blocks)
      if (nn::GemmPlan p{nn::GemmBackend::Tiled, tile, b}; nn::to_string(p) != nn::to_string(plans.front()))
        plans.push_back(p);
    if (!quick) plans.push_back({nn::GemmBackend::CLBlast, tile});
    for (const auto& plan : plans) {
      nn::Gemm g(ctx, plan);
      auto run = [&] {
        g.run(nn::Op::N, nn::Op::N, rows, n, k, 1.0f, nn::mat(da, k), nn::mat(dw, n), 0.0f, nn::mat(dc, n));
        ctx.finish();
      };
      run();
      const double gf = flops / best_of(plan.backend == nn::GemmBackend::CLBlast ? 2 : 3, run) * 1e-9;
      // A figure for a wrong product is worthless: check it against OpenBLAS's (a TF32 plan within its bound, with
      // Σ|a·b| ≤ k for factors in [-1, 1]).
      const auto got = dc.read();
      double err = 0, scale = 0;
      for (std::size_t i = 0; i < got.size(); ++i) {
        err = std::max(err, double(std::abs(got[i] - c[i])));
        scale = std::max(scale, double(std::abs(c[i])));
      }
      const bool tf32 = plan.backend == nn::GemmBackend::Tiled && plan.block.tf32;
      if (err > (tf32 ? nn::tf32_error_bound(double(k)) : 1e-4 * scale)) {
        std::fprintf(stderr, "bench_nn: %s GEMM differs from OpenBLAS by %g (max |C| %g)\n",
                     nn::to_string(g.plan()).c_str(), err, scale);
        return 1;
      }
      // A fraction of peak above 1 is a probe that missed the device's limit, not a fast GEMM: say so, fail. The
      // tensor cores (TF32) are not the FMA units: their figure is printed against the FMA peak for comparison only.
      if (gf > peak && !tf32) {
        std::fprintf(stderr, "bench_nn: %s GEMM at %.1f GFLOP/s is above the measured FMA peak %.1f\n",
                     nn::to_string(g.plan()).c_str(), gf, peak);
        above_peak = true;
      }
      gemm_rows.push_back({{"backend", nn::to_string(g.backend())},
                           {"plan", nn::to_string(g.plan())},
                           {"rows", rows},
                           {"gflops", gf},
                           {"openblas_gflops", blas},
                           {"openblas_core", openblas_get_corename()},
                           {"peak_gflops", peak}});
      if (!json)
        std::printf(
            "GEMM (%zux512)·(512x512) %-18s %7.1f GFLOP/s  (%.0f%% of FMA peak; OpenBLAS %.1f GFLOP/s, ratio %.2f)\n",
            rows, nn::to_string(g.plan()).c_str(), gf, 100 * gf / peak, blas, gf / blas);
    }
  }
  // The I-Module's MLP (59 → 3 × 64 → 32), inference and a training forward + backward (its hash grid's 8 input
  // columns' gradient kept, as the I-Module asks): the fused kernels against per-layer GEMMs.
  nlohmann::json small_json;
  {
    const std::size_t rows = quick ? 16384 : 65536;
    nn::Gemm g(ctx, nn::GemmChoice::Own);
    nn::MlpConfig mc;
    mc.inputs = 59;
    mc.width = 64;
    mc.hidden_layers = 3;
    mc.outputs = 32;
    std::vector<float> x(rows * mc.inputs), d(rows * mc.outputs);
    for (auto& v : x) v = u(rng);
    for (auto& v : d) v = u(rng);
    cl::Buffer<float> dx(ctx, std::span<const float>(x)), dy(ctx, std::span<const float>(d)),
        out(ctx, rows * mc.outputs), d_in(ctx, rows * mc.inputs);
    double infer_ms[2], step_ms[2];
    for (int fused = 1; fused >= 0; --fused) {
      mc.small_path = fused == 1 ? nn::MlpConfig::SmallPath::Fused : nn::MlpConfig::SmallPath::Layers;
      nn::Mlp m(ctx, g, mc, 1);
      nn::MlpContext mctx;
      auto infer = [&] {
        m.infer(dx, rows, out);
        ctx.finish();
      };
      auto step = [&] {
        m.forward_train(dx, rows, mctx);
        m.backward(mctx, dy, &d_in, 8);
        ctx.finish();
      };
      infer();
      step();
      infer_ms[fused] = 1000 * best_of(5, infer);
      step_ms[fused] = 1000 * best_of(5, step);
    }
    small_json = {{"rows", rows},
                  {"fused_ms", infer_ms[1]},
                  {"layers_ms", infer_ms[0]},
                  {"fused_step_ms", step_ms[1]},
                  {"layers_step_ms", step_ms[0]}};
    if (!json) {
      std::printf("I-Module MLP inference, %zu rows: fused %.2f ms, per-layer GEMMs %.2f ms\n", rows, infer_ms[1],
                  infer_ms[0]);
      std::printf("I-Module MLP forward + backward, %zu rows: fused %.2f ms, per-layer GEMMs %.2f ms\n", rows,
                  step_ms[1], step_ms[0]);
    }
  }

  // One N-Module training step (docs/design.md §2) at the batch the device trains with.
  const std::size_t B = quick ? 4096 : 16384, N = 4;
  const StepTime st = nmodule_step(ctx, B, quick ? 2 : 5, rng);
  const double ours_ms = st.ms;
  const int reps = st.reps;
  const double torch_ms = torch_anchor_ms(B);
  if (!json) {
    std::printf("N-Module step (hash grid %zux%zu T=2^%zu + 4x512 MLP, B=%zu, +%zu·B inference), GEMM %s:\n", st.levels,
                st.features, st.log2_table, B, N, st.plan.c_str());
    std::printf(
        "  ours    %8.1f ms (median of %d; forward %.0f, inference %.0f, loss+backward %.0f, adam %.0f ms avg)\n",
        ours_ms, reps, st.fwd_ms, st.inf_ms, st.bwd_ms, st.adam_ms);
    std::printf("  peak device memory of a step: %.1f MiB (%zu parameters)\n", st.peak_mib, st.parameters);
    if (torch_ms > 0)
      std::printf("  PyTorch %8.1f ms (bench/torch_anchor.py, CPU)  ->  ours is %.2fx faster\n", torch_ms,
                  torch_ms / ours_ms);
    else
      std::printf("  PyTorch anchor unavailable (python3 with torch not importable)\n");
  }
  if (json) {
    nlohmann::json step_json = {{"ours_ms", ours_ms},
                                {"pytorch_ms", torch_ms > 0 ? nlohmann::json(torch_ms) : nlohmann::json()}};
    std::cout << nlohmann::json{{"gemm", gemm_rows}, {"step", step_json}, {"small_mlp", small_json}}.dump() << "\n";
  }
  return above_peak ? 1 : 0;
}
