#pragma once
// Matrix products for the networks, on one of two backends chosen per device (DESIGN.md §6):
//   own      kernels/gemm.cl, register-blocked without local memory: fast on PoCL's CPU device;
//   clblast  CLBlast's tuned kernels on our cl_mem and queue: fast on GPUs, untuned (slow) on PoCL.
// `auto` times both on a 4096×512×512 product once per device and driver and caches the winner
// ($XDG_CACHE_HOME/clradiosity/gemm_backend.json, else ~/.cache/...).
#include <cstddef>
#include <optional>
#include <string>

#include "cl/buffer.hpp"
#include "cl/context.hpp"
#include "cl/kernel.hpp"

namespace clr::nn {

enum class GemmBackend { Own, CLBlast };
enum class GemmChoice { Auto, Own, CLBlast };
enum class Op { N, T };                            // op(X) = X or Xᵀ
enum class Act : unsigned { None = 0, Relu = 1 };  // values match ACT_* in kernels/gemm.cl

// "auto" | "own" | "clblast" (the engine config's `gemm` entry); anything else throws InputError.
GemmChoice parse_gemm_choice(const std::string& text);
std::string to_string(GemmBackend backend);

// A row-major matrix inside a buffer: element (i, j) is at buf[offset + i·ld + j].
struct MatRef {
  const cl::Buffer<float>* buf;
  std::size_t offset;
  std::size_t ld;
};
inline MatRef mat(const cl::Buffer<float>& b, std::size_t ld, std::size_t offset = 0) { return {&b, offset, ld}; }

// Applied to every output element after the product: C = act(alpha·op(A)·op(B) + beta·C + bias[column]).
struct Epilogue {
  const cl::Buffer<float>* bias = nullptr;  // bias[column] at bias->offset + column
  std::size_t bias_offset = 0;
  Act act = Act::None;
};

class Gemm {
 public:
  Gemm(cl::Context& ctx, GemmChoice choice = GemmChoice::Auto);

  GemmBackend backend() const { return backend_; }

  // C[m×n] = act(alpha · op(A)[m×k] · op(B)[k×n] + beta · C + bias). With beta == 0, C is not read.
  void run(Op op_a, Op op_b, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b, float beta,
           MatRef c, const Epilogue& epilogue = {});

 private:
  void run_own(Op op_a, Op op_b, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b,
               float beta, MatRef c, const Epilogue& epilogue);
  void run_clblast(Op op_a, Op op_b, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b,
                   float beta, MatRef c, const Epilogue& epilogue);
  void run_narrow(Op op_a, std::size_t m, std::size_t n, std::size_t k, float alpha, MatRef a, MatRef b, float beta,
                  MatRef c, const Epilogue& epilogue);
  cl::Buffer<float>& scratch(std::optional<cl::Buffer<float>>& slot, std::size_t count);

  cl::Context* ctx_;
  GemmBackend backend_;
  std::size_t tm_ = 8, tn_ = 32;
  std::optional<cl::Kernel> gemm_, reduce_, transpose_, bias_act_, narrow_nn_, narrow_tn_, zero_;
  std::optional<cl::Buffer<float>> transposed_b_, partials_, narrow_bt_;
};

// Times both backends on this device (a few hundred ms) and returns the faster; the result is cached on disk
// keyed by device name and driver version, so later runs pay nothing.
GemmBackend probe_gemm_backend(cl::Context& ctx);

// Checked narrowing for kernel arguments: kernels index with 32-bit integers (buffers are ≤ 1 GiB on PoCL).
unsigned u32(std::size_t v);

}  // namespace clr::nn
