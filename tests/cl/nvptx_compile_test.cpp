// NVIDIA's compile target without an NVIDIA card: every program the host builds (nn/programs.hpp, the same list
// the host's code builds from), composed as cl::Program composes it and with the -D options the host passes on an
// NVIDIA device, compiled by clang for nvptx64-nvidia-nvcl as OpenCL C 1.2 with NVIDIA's extensions only (no
// cl_khr_fp16, no float atomics; int64 atomics and fp64 present) and libclc's NVIDIA builtins linked in.
// Skipped where clang-15 or libclc-15 is missing (tests/runtimes/lanes.cmake finds them). What this cannot see:
// NVIDIA's own compiler and driver, its register allocation, and anything at run time (docs/nvidia.md).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "cl/program.hpp"
#include "nn/programs.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

// The extensions NVIDIA's OpenCL reports that change what a kernel may use; everything else is off.
constexpr const char* kNvidiaExtensions =
    "-all,+cl_khr_byte_addressable_store,+cl_khr_global_int32_base_atomics,+cl_khr_global_int32_extended_atomics,"
    "+cl_khr_local_int32_base_atomics,+cl_khr_local_int32_extended_atomics,+cl_khr_int64_base_atomics,"
    "+cl_khr_int64_extended_atomics,+cl_khr_fp64,+cl_khr_3d_image_writes";

cl::DeviceInfo nvidia_device() {
  cl::DeviceInfo d;
  d.platform_name = "NVIDIA CUDA";
  d.name = "NVIDIA GPU (emulated for the compile test)";
  d.type = cl::DeviceType::Gpu;
  d.compute_units = 132;
  d.global_mem_bytes = 80ull << 30;
  d.max_alloc_bytes = d.global_mem_bytes;
  d.max_work_group_size = 1024;
  d.local_mem_bytes = 48 * 1024;
  d.int64_atomics = true;
  d.nv_compute_capability = 90;  // Hopper: the TF32 tensor-core GEMM is built too
  cl::emulate_nvidia_limits(d);
  return d;
}

struct Compiled {
  int status = -1;
  std::string messages;
  std::string ptx;
};

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Compiles `source` with `options` the way NVIDIA's driver would see it.
Compiled compile_for_nvptx(const std::string& name, const std::string& source, const std::string& options) {
  const fs::path dir = fs::temp_directory_path() / ("clr_nvptx_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path src = dir / (name + ".cl"), ptx = dir / (name + ".ptx"), log = dir / (name + ".log");
  std::ofstream(src, std::ios::binary) << source;
  // The linker warning about libclc's triple spelling (nvptx64-unknown-nvidiacl) is expected and silenced.
  const std::string command =
      std::string("'") + CLR_NVPTX_CLANG + "' -x cl -cl-std=CL1.2 -target nvptx64-nvidia-nvcl" +
      " -O2 -Wno-linker-warnings -Xclang -finclude-default-header -Xclang -cl-ext=" + kNvidiaExtensions +
      " -Xclang -mlink-builtin-bitcode -Xclang '" + CLR_NVPTX_LIBCLC + "' " + options + " -S -o '" + ptx.string() +
      "' '" + src.string() + "' 2> '" + log.string() + "'";
  Compiled out;
  const int raw = std::system(command.c_str());
  out.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  out.messages = read_file(log);
  if (out.status == 0) out.ptx = read_file(ptx);
  fs::remove_all(dir);
  return out;
}

bool tools_present(std::string& why) {
  if (std::string(CLR_NVPTX_CLANG).empty())
    why = "clang-15 not found (apt-get install clang-15)";
  else if (std::string(CLR_NVPTX_LIBCLC).empty())
    why = "libclc's nvptx64--nvidiacl.bc not found (apt-get install libclc-15)";
  return why.empty();
}

class NvptxCompile : public ::testing::TestWithParam<nn::programs::Build> {};

TEST_P(NvptxCompile, CompilesAsTheHostComposesIt) {
  std::string why;
  if (!tools_present(why)) GTEST_SKIP() << why;
  const auto& build = GetParam();
  const auto got = compile_for_nvptx(build.name, cl::compose_source(build.files), build.options);
  ASSERT_EQ(got.status, 0) << "clang for nvptx64-nvidia-nvcl failed on " << build.name << " with options '"
                           << build.options << "':\n"
                           << got.messages;
  // Every program defines kernels; PTX without an entry would mean nothing was compiled.
  EXPECT_THAT(got.ptx, ::testing::HasSubstr(".entry ")) << build.name;
  // A builtin neither libclc nor the program defines stays an external call, which the driver would refuse.
  EXPECT_THAT(got.ptx, ::testing::Not(::testing::HasSubstr(".extern .func"))) << build.name;
}

INSTANTIATE_TEST_SUITE_P(EveryHostProgram, NvptxCompile,
                         ::testing::ValuesIn(nn::programs::every_build(nvidia_device())),
                         [](const ::testing::TestParamInfo<nn::programs::Build>& p) { return p.param.name; });

// The compile test's own check: what NVIDIA lacks must fail here too, or the test above could pass vacuously.
TEST(NvptxCompileTarget, RefusesWhatNvidiaLacks) {
  std::string why;
  if (!tools_present(why)) GTEST_SKIP() << why;
  const auto fp16 =
      compile_for_nvptx("fp16", "__kernel void k(__global float* x) { half h = (half)x[0]; x[0] = h; }\n", "");
  EXPECT_NE(fp16.status, 0) << "half arithmetic compiled without cl_khr_fp16";
  const auto c20 = compile_for_nvptx(
      "float_atomic", "__kernel void k(volatile __global atomic_float* x) { atomic_fetch_add(x, 1.0f); }\n", "");
  EXPECT_NE(c20.status, 0) << "an OpenCL 2.0 float atomic compiled as OpenCL C 1.2";
  const auto ok =
      compile_for_nvptx("plain", "__kernel void k(__global float* x) { x[get_global_id(0)] *= 2.0f; }\n", "");
  EXPECT_EQ(ok.status, 0) << ok.messages;
}

TEST(NvptxCompileTarget, TheListHoldsEveryKernelFileTheHostBuilds) {
  // Every kernel file is part of some host program but the bench's peak.cl and the tests' reduce.cl.
  std::set<std::string> used;
  for (const auto& b : nn::programs::every_build(nvidia_device())) used.insert(b.files.begin(), b.files.end());
  for (const auto& entry : fs::directory_iterator(fs::path(CLR_SOURCE_DIR) / "kernels")) {
    const auto name = entry.path().filename().string();
    if (entry.path().extension() != ".cl" || name == "peak.cl" || name == "reduce.cl") continue;
    EXPECT_TRUE(used.count(name)) << name << " is in no program of nn/programs.hpp";
  }
}

TEST(NvptxCompileTarget, HostCodeBuildsProgramsOnlyFromTheList) {
  // A program composed inline (ctx.program({"x.cl"}, ...)) would escape the compile test above.
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(CLR_SOURCE_DIR) / "host")) {
    if (entry.path().extension() != ".cpp") continue;
    ++files;
    const std::string text = read_file(entry.path());
    EXPECT_FALSE(std::regex_search(text, std::regex(R"(\.program\(\s*\{)")))
        << entry.path() << " composes a program inline; name it in nn/programs.hpp";
  }
  EXPECT_GT(files, 10u);
}

}  // namespace
}  // namespace clr::test
