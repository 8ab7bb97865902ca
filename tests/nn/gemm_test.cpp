// Both GEMM backends against a double-precision twin, over every transpose the layers use, edge tiles,
// split-K, and the fused bias + ReLU epilogue; canaries after C catch writes past the matrix.
#include "nn/gemm.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <random>

#include "common/error.hpp"
#include "nn/programs.hpp"
#include "support/cl_fixture.hpp"
#include "support/tolerance.hpp"

namespace clr::test {
namespace {

struct Case {
  nn::Op op_a, op_b;
  std::size_t m, n, k;
  float alpha, beta;
  bool bias;
  nn::Act act;
};

class GemmTest : public ClTest {
 protected:
  // `on` is the context `gemm` was made on (the fixture's, or a GPU-shaped one).
  void check(nn::Gemm& gemm, const Case& c) { check(ctx(), gemm, c); }
  void check(cl::Context& on, nn::Gemm& gemm, const Case& c) {
    std::mt19937 rng(unsigned(c.m * 131 + c.n * 7 + c.k));
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    // Stored shapes: A is [m × k] or [k × m]; B is [k × n] or [n × k]. Leading dims padded by 3 so a kernel that
    // assumed packed rows would fail.
    const std::size_t a_rows = c.op_a == nn::Op::N ? c.m : c.k, a_cols = c.op_a == nn::Op::N ? c.k : c.m;
    const std::size_t b_rows = c.op_b == nn::Op::N ? c.k : c.n, b_cols = c.op_b == nn::Op::N ? c.n : c.k;
    const std::size_t lda = a_cols + 3, ldb = b_cols + 3, ldc = c.n + 3, off = 5;
    std::vector<float> a(off + a_rows * lda), b(off + b_rows * ldb), bias(c.n), cm(off + c.m * ldc);
    for (auto* v : {&a, &b, &bias, &cm})
      for (auto& x : *v) x = u(rng);
    // With beta = 0, C must not be read: NaN there would poison 0·C.
    if (c.beta == 0.0f)
      for (auto& x : cm) x = std::numeric_limits<float>::quiet_NaN();
    auto A = [&](std::size_t i, std::size_t kk) {
      return double(c.op_a == nn::Op::N ? a[off + i * lda + kk] : a[off + kk * lda + i]);
    };
    auto B = [&](std::size_t kk, std::size_t j) {
      return double(c.op_b == nn::Op::N ? b[off + kk * ldb + j] : b[off + j * ldb + kk]);
    };
    // A TF32 plan (tensor cores, NVIDIA only) rounds each factor to 10 mantissa bits: its elements are held to
    // nn::tf32_error_bound of |alpha| · Σ|A·B| on top of the FP32 tolerance.
    const bool tf32 = gemm.plan().backend == nn::GemmBackend::Tiled && gemm.plan().block.tf32;
    std::vector<double> want(c.m * c.n), slack(c.m * c.n);
    for (std::size_t i = 0; i < c.m; ++i)
      for (std::size_t j = 0; j < c.n; ++j) {
        double s = 0, mag = 0;
        for (std::size_t kk = 0; kk < c.k; ++kk) {
          s += A(i, kk) * B(kk, j);
          mag += std::abs(A(i, kk) * B(kk, j));
        }
        slack[i * c.n + j] = tf32 ? nn::tf32_error_bound(std::abs(c.alpha) * mag) : 0.0;
        double r = c.alpha * s + (c.beta != 0.0f ? c.beta * double(cm[off + i * ldc + j]) : 0.0) +
                   (c.bias ? double(bias[j]) : 0.0);
        if (c.act == nn::Act::Relu) r = std::max(r, 0.0);
        want[i * c.n + j] = r;
      }
    cl::Buffer<float> da(on, std::span<const float>(a)), db(on, std::span<const float>(b)),
        dbias(on, std::span<const float>(bias));
    auto c_host = with_canaries(cm.size());
    std::copy(cm.begin(), cm.end(), c_host.begin());
    cl::Buffer<float> dc(on, std::span<const float>(c_host));
    gemm.run(c.op_a, c.op_b, c.m, c.n, c.k, c.alpha, nn::mat(da, lda, off), nn::mat(db, ldb, off), c.beta,
             nn::mat(dc, ldc, off), {c.bias ? &dbias : nullptr, 0, c.act});
    dc.read(c_host);
    std::vector<float> got(c.m * c.n);
    for (std::size_t i = 0; i < c.m; ++i)
      for (std::size_t j = 0; j < c.n; ++j) got[i * c.n + j] = c_host[off + i * ldc + j];
    EXPECT_TRUE(all_near(std::span<const float>(got), std::span<const double>(want), kFloatKernel,
                         std::span<const double>(slack)))
        << "m=" << c.m << " n=" << c.n << " k=" << c.k << " opA=" << int(c.op_a) << " opB=" << int(c.op_b);
    EXPECT_TRUE(canaries_intact(c_host, cm.size()));
    // The padding between rows (ld > n) must be untouched.
    for (std::size_t i = 0; i < c.m; ++i)
      for (std::size_t j = c.n; j < ldc && off + i * ldc + j < cm.size(); ++j)
        ASSERT_EQ(std::bit_cast<std::uint32_t>(c_host[off + i * ldc + j]),
                  std::bit_cast<std::uint32_t>(cm[off + i * ldc + j]))
            << "row padding written at " << i << "," << j;
  }

  std::vector<Case> cases() {
    using nn::Act;
    using nn::Op;
    return {
        {Op::N, Op::N, 64, 64, 64, 1.0f, 0.0f, false, Act::None},    // full tiles only
        {Op::N, Op::N, 37, 45, 19, 1.0f, 0.0f, true, Act::Relu},     // edge tiles in m and n, fused epilogue
        {Op::N, Op::N, 40, 3, 70, 1.0f, 0.0f, true, Act::None},      // the narrow output layer
        {Op::N, Op::T, 33, 70, 3, 1.0f, 0.0f, false, Act::None},     // dX = dZ·Wᵀ of the output layer
        {Op::N, Op::T, 48, 96, 64, 0.5f, 0.0f, false, Act::None},    // dX = dZ·Wᵀ
        {Op::T, Op::N, 70, 3, 300, 1.0f, 1.0f, false, Act::None},    // dW of the output layer, accumulated
        {Op::T, Op::N, 64, 64, 1100, 1.0f, 1.0f, false, Act::None},  // dW = Xᵀ·dZ: split-K on small devices
        {Op::T, Op::T, 20, 30, 40, -2.0f, 0.25f, false, Act::None},  // both transposed
    };
  }
};

// Every candidate tile of CPUs and GPUs, not only the one the probe picks here: another device picks another.
TEST_F(GemmTest, OwnKernelMatchesTwinWithEveryTile) {
  std::vector<nn::GemmTile> tiles;
  for (const cl::DeviceType type : {cl::DeviceType::Cpu, cl::DeviceType::Gpu}) {
    cl::DeviceInfo device = ctx().device();
    device.type = type;
    for (const auto& t : nn::gemm_tiles(device)) tiles.push_back(t);
  }
  for (const auto& tile : tiles) {
    nn::Gemm gemm(ctx(), nn::GemmPlan{nn::GemmBackend::Own, tile});
    SCOPED_TRACE(nn::to_string(gemm.plan()));
    for (const auto& c : cases()) check(gemm, c);
  }
}

// The local-memory tiled kernel at every block of CPUs and GPUs, on the engine's transposes and sizes that leave
// ragged edges in every dimension of a block (rows, columns and the bk-deep k steps). The narrow output layer
// (n ≤ 4 with op(B) = B) runs gemm_narrow_nn whatever the plan and is tested above.
TEST_F(GemmTest, TiledKernelMatchesTwinWithEveryBlock) {
  using nn::Act;
  using nn::Op;
  std::vector<Case> tiled_cases;
  std::vector<nn::GemmBlock> blocks;
  if (ctx().device().simulator) {
    // Oclgrind interprets every work-item (the full list takes ~8 minutes there): two blocks, small products that
    // still leave every edge ragged, each transpose, and a k long enough for split-K on its GPU-typed device.
    tiled_cases = {{Op::N, Op::N, 37, 45, 19, 1.0f, 0.0f, true, Act::Relu},
                   {Op::N, Op::T, 70, 66, 20, 0.5f, 0.0f, false, Act::None},
                   {Op::T, Op::N, 40, 70, 520, 1.0f, 1.0f, false, Act::None},
                   {Op::T, Op::T, 20, 30, 40, -2.0f, 0.25f, false, Act::None}};
    cl::DeviceInfo gpu = ctx().device();
    gpu.type = cl::DeviceType::Gpu;
    gpu.nv_compute_capability = 90;
    // The scalar block and the first float4 one (vector reads of local memory, under the race and bounds checks),
    // and the smallest TF32 block of each buffering (emulated as in GpuShapedDeviceMatchesTwin; Oclgrind offers
    // 32 KiB of local memory): the race check is what sees a missing barrier between the double buffer's stores and
    // another warp's reads.
    for (const auto& b : nn::gemm_blocks(gpu))
      if (blocks.empty() || (b.vec == 4 && blocks.size() == 1) || (b.tf32 && b.bm == 64 && b.bn == 64))
        blocks.push_back(b);
  } else {
    for (const auto& c : cases())
      if (!(c.n <= 4 && c.op_b == Op::N)) tiled_cases.push_back(c);
    tiled_cases.push_back({Op::N, Op::N, 131, 70, 37, 1.0f, 0.0f, true, Act::Relu});    // past one block, k ragged
    tiled_cases.push_back({Op::T, Op::N, 70, 129, 300, 1.0f, 1.0f, false, Act::None});  // dW, accumulated
    tiled_cases.push_back({Op::N, Op::T, 65, 140, 66, 1.0f, 0.0f, false, Act::None});   // dX = dZ·Wᵀ
    for (const cl::DeviceType type : {cl::DeviceType::Cpu, cl::DeviceType::Gpu}) {
      cl::DeviceInfo device = ctx().device();
      device.type = type;
      for (const auto& b : nn::gemm_blocks(device)) blocks.push_back(b);
    }
  }
  for (const auto& block : blocks) {
    nn::Gemm gemm(ctx(), nn::GemmPlan{nn::GemmBackend::Tiled, nn::gemm_tiles(ctx().device()).front(), block});
    SCOPED_TRACE(nn::to_string(gemm.plan()));
    for (const auto& c : tiled_cases) check(gemm, c);
  }
}

// The launch shape (split-K, work-groups) follows the device's type and size: on a device that reports itself as a
// large GPU (an H200's 132 compute units) the same products, forward layers with their epilogue and long k
// included, still match the twin. The first H200 run found forward products split there, which threw.
// It reports compute capability 9.0 too, so the TF32 blocks join, built with their two PTX instructions emulated
// (gemm_tf32.cl): their tiling, fragment layout and double buffering are checked here, on every lane.
TEST_F(GemmTest, GpuShapedDeviceMatchesTwin) {
  using nn::Act;
  using nn::Op;
  cl::DeviceInfo gpu = ctx().device();
  gpu.type = cl::DeviceType::Gpu;
  gpu.compute_units = 132;
  gpu.nv_compute_capability = 90;
  cl::Context on(gpu);
  std::vector<Case> gpu_cases = cases();
  gpu_cases.push_back({Op::N, Op::N, 37, 45, 600, 1.0f, 0.0f, true, Act::Relu});    // a hidden layer, k ≥ 2 slices
  gpu_cases.push_back({Op::N, Op::N, 40, 64, 520, 1.0f, 0.0f, true, Act::None});    // bias alone
  gpu_cases.push_back({Op::T, Op::N, 40, 70, 1100, 1.0f, 1.0f, false, Act::None});  // dW: split
  std::vector<nn::GemmPlan> plans;
  for (const auto& t : nn::gemm_tiles(gpu)) plans.push_back({nn::GemmBackend::Own, t});
  for (const auto& b : nn::gemm_blocks(gpu)) plans.push_back({nn::GemmBackend::Tiled, nn::gemm_tiles(gpu).front(), b});
  for (const auto& plan : plans) {
    nn::Gemm gemm(on, plan);
    SCOPED_TRACE(nn::to_string(gemm.plan()));
    for (const auto& c : gpu_cases) check(on, gemm, c);
  }
}

// Every block stays within NVIDIA's limits (48 KiB of local memory, 1024 work-items a group), and the compiled
// kernel reports at least the host's count of a block's local memory, within the same limit. At least, not exactly:
// NVIDIA's compiler adds a few bytes of its own (4 on an H200, driver 580); the launch check reads the kernel's figure.
// TF32 blocks are checked for their shape here (gemm_tf32.cl's #error conditions: a warp of lanes in dimension 0,
// an even number of warps, m16n8 fragments filling a lane's accumulators); their program holds inline PTX, so it
// builds only on NVIDIA (the nvptx lane compiles it, the GPU acceptance runs it against the twin).
TEST_F(GemmTest, TiledBlocksFitNvidiasLimits) {
  cl::DeviceInfo gpu = ctx().device();
  gpu.type = cl::DeviceType::Gpu;
  gpu.nv_compute_capability = 90;
  for (const auto& b : nn::gemm_blocks(gpu)) {
    const auto name = nn::to_string(nn::GemmPlan{nn::GemmBackend::Tiled, {1, 1, 1}, b});
    EXPECT_LE(b.group_columns() * b.group_rows(), 1024u) << name;
    EXPECT_LE(b.local_bytes(), 48u * 1024u) << name;
    EXPECT_EQ(b.bm % b.wm, 0u) << name;
    EXPECT_EQ(b.bn % b.wn, 0u) << name;
    if (b.vec == 4) {
      EXPECT_EQ(b.wm % 4, 0u) << name;  // runs of 4 rows and columns
      EXPECT_EQ(b.wn % 4, 0u) << name;
    }
    if (b.tf32) {
      const unsigned warps = b.bm / b.wm, mt = b.bm / 2 / 16, nt = b.bn / (warps / 2) / 8;
      EXPECT_EQ(b.group_columns(), 32u) << name;
      EXPECT_EQ(warps % 2, 0u) << name;
      EXPECT_EQ(mt * nt * 4, b.wm * b.wn) << name;
      EXPECT_EQ(b.bk % 8, 0u) << name;
      continue;
    }
    const cl::Kernel k =
        ctx().program(nn::programs::gemm_tiled, nn::programs::gemm_tiled_options(b)).kernel("gemm_tiled");
    EXPECT_GE(k.local_mem_bytes(), b.local_bytes()) << name;
    EXPECT_LE(k.local_mem_bytes(), 48u * 1024u) << name;
  }
}

// Tensor-core blocks are offered only to NVIDIA devices of compute capability 8.0 and later.
TEST(GemmBlocks, Tf32OnlyFromAmpereOn) {
  cl::DeviceInfo gpu;
  gpu.type = cl::DeviceType::Gpu;
  const auto tf32_count = [&] {
    const auto blocks = nn::gemm_blocks(gpu);
    return std::count_if(blocks.begin(), blocks.end(), [](const nn::GemmBlock& b) { return b.tf32; });
  };
  EXPECT_EQ(tf32_count(), 0);
  gpu.nv_compute_capability = 75;
  EXPECT_EQ(tf32_count(), 0);
  gpu.nv_compute_capability = 80;
  EXPECT_GT(tf32_count(), 0);
  gpu.type = cl::DeviceType::Cpu;
  EXPECT_EQ(tf32_count(), 0);
}

TEST_F(GemmTest, ClblastMatchesTwin) {
  nn::Gemm gemm(ctx(), nn::GemmChoice::CLBlast);
  for (const auto& c : cases()) check(gemm, c);
}

TEST(GemmChoice, ParsesConfigValues) {
  EXPECT_EQ(nn::parse_gemm_choice("own"), nn::GemmChoice::Own);
  EXPECT_EQ(nn::parse_gemm_choice("clblast"), nn::GemmChoice::CLBlast);
  EXPECT_EQ(nn::parse_gemm_choice("auto"), nn::GemmChoice::Auto);
  EXPECT_EQ(nn::parse_gemm_choice("fp32"), nn::GemmChoice::Fp32);
  EXPECT_THROW(nn::parse_gemm_choice("cublas"), InputError);
}

}  // namespace
}  // namespace clr::test
