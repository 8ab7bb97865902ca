// Program cache, build-error reporting, the kernel-directory override and launch limits.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include "cl/buffer.hpp"
#include "cl/kernel_source.hpp"
#include "common/error.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// Points CLRADIOSITY_KERNEL_DIR at a fresh folder for one test.
class KernelDir {
 public:
  KernelDir() : dir_(fs::temp_directory_path() / ("clr_kernels_" + std::to_string(::getpid()))) {
    fs::create_directories(dir_);
    setenv("CLRADIOSITY_KERNEL_DIR", dir_.c_str(), 1);
  }
  ~KernelDir() {
    unsetenv("CLRADIOSITY_KERNEL_DIR");
    fs::remove_all(dir_);
  }
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }

 private:
  fs::path dir_;
};

TEST(KernelSource, EveryKernelFileIsEmbedded) {
  const auto files = cl::embedded_kernel_files();
  for (const auto& entry : fs::directory_iterator(fs::path(CLR_SOURCE_DIR) / "kernels")) {
    if (entry.path().extension() != ".cl") continue;
    const auto name = entry.path().filename().string();
    EXPECT_NE(std::find(files.begin(), files.end(), name), files.end()) << name;
    std::ifstream in(entry.path());
    const std::string on_disk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(cl::kernel_source(name), on_disk) << name << " differs from its embedded copy";
  }
}

TEST(KernelSource, OverrideDirectoryIsRead) {
  KernelDir dir;
  dir.write("util.cl", "// from disk\n");
  EXPECT_EQ(cl::kernel_source("util.cl"), "// from disk\n");
  EXPECT_THROW(cl::kernel_source("missing.cl"), InputError);
}

TEST_F(ClTest, ProgramsAreBuiltOncePerFilesAndOptions) {
  const auto before = ctx().programs_built();
  const auto& a = ctx().program({"atomics.cl", "reduce.cl"}, "-DCLR_CACHE_TEST=1");
  const auto& b = ctx().program({"atomics.cl", "reduce.cl"}, "-DCLR_CACHE_TEST=1");
  EXPECT_EQ(a.get(), b.get());
  EXPECT_EQ(ctx().programs_built(), before + 1);
  const auto& c = ctx().program({"atomics.cl", "reduce.cl"}, "-DCLR_CACHE_TEST=2");
  EXPECT_NE(a.get(), c.get());
  EXPECT_EQ(ctx().programs_built(), before + 2);
}

// The compiler's warnings stay in the program's build log, off the terminal; CLRADIOSITY_KERNEL_WARNINGS=error (the
// test lane that checks every kernel builds clean) makes them a build failure naming the files.
TEST_F(ClTest, KernelWarningsStayInTheBuildLog) {
  const char* lane = std::getenv("CLRADIOSITY_KERNEL_WARNINGS");  // the ci preset's, restored at the end
  const std::string lane_value = lane ? lane : "";
  {
    KernelDir dir;
    dir.write("warned.cl",
              "#warning \"clr kernel warning test\"\n__kernel void warned(__global float* x) { x[0] = 1.0f; }\n");
    unsetenv("CLRADIOSITY_KERNEL_WARNINGS");
    ::testing::internal::CaptureStderr();
    const auto& program = ctx().program({"warned.cl"}, "-DCLR_WARNED=1");
    const std::string printed = ::testing::internal::GetCapturedStderr();
    EXPECT_THAT(program.build_log(), HasSubstr("clr kernel warning test"));
    EXPECT_TRUE(cl::has_warning(program.build_log()));
    EXPECT_THAT(printed, ::testing::Not(HasSubstr("warning"))) << "the compiler's chatter reached stderr";

    setenv("CLRADIOSITY_KERNEL_WARNINGS", "error", 1);
    try {
      ctx().program({"warned.cl"}, "-DCLR_WARNED=2");
      FAIL() << "a kernel with a warning built under CLRADIOSITY_KERNEL_WARNINGS=error";
    } catch (const cl::Error& e) {
      EXPECT_EQ(e.status(), CL_BUILD_PROGRAM_FAILURE);
      EXPECT_THAT(e.what(), HasSubstr("warned.cl"));
      EXPECT_THAT(e.what(), HasSubstr("clr kernel warning test"));
    }
  }
  if (lane)
    setenv("CLRADIOSITY_KERNEL_WARNINGS", lane_value.c_str(), 1);
  else
    unsetenv("CLRADIOSITY_KERNEL_WARNINGS");
  // The clean kernels the engine builds have an empty log, or one without warnings.
  EXPECT_FALSE(cl::has_warning(ctx().program({"atomics.cl", "reduce.cl"}, "-DCLR_WARNED=3").build_log()));
}

TEST_F(ClTest, BuildErrorCarriesTheBuildLog) {
  KernelDir dir;
  dir.write("broken.cl", "__kernel void broken(__global float* x) {\n  x[0] = undeclared_name;\n}\n");
  try {
    ctx().program({"broken.cl"});
    FAIL() << "a broken kernel built";
  } catch (const cl::Error& e) {
    EXPECT_EQ(e.status(), CL_BUILD_PROGRAM_FAILURE);
    EXPECT_THAT(e.what(), HasSubstr("broken.cl"));
    EXPECT_THAT(e.what(), HasSubstr("undeclared_name")) << "the build log is missing";
  }
  // A failed build is not cached: fixing the file makes the next request build.
  dir.write("broken.cl", "__kernel void broken(__global float* x) { x[0] = 1.0f; }\n");
  EXPECT_NO_THROW(ctx().program({"broken.cl"}).kernel("broken"));
}

TEST_F(ClTest, UnknownKernelNameIsNamed) {
  try {
    ctx().program({"atomics.cl", "reduce.cl"}).kernel("no_such_kernel");
    FAIL();
  } catch (const cl::Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no_such_kernel"));
  }
}

TEST_F(ClTest, OversizedWorkGroupIsRefused) {
  auto k = ctx().program({"atomics.cl", "reduce.cl"}).kernel("fill_f32");
  cl::Buffer<float> buf(ctx(), 16);
  k.args(buf, 16u, 0.0f);
  EXPECT_GT(k.work_group_size(), 0u);
  EXPECT_LE(k.work_group_size(), ctx().device().max_work_group_size) << "capped by the device (and its emulation)";
  try {
    k.launch(k.work_group_size() * 2, k.work_group_size() * 2);
    FAIL() << "a work-group twice the kernel's limit was enqueued";
  } catch (const cl::Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("fill_f32"));
    EXPECT_THAT(e.what(), HasSubstr("exceeds its limit"));
  }
}

TEST_F(ClTest, OversizedLocalMemoryIsRefusedBeforeEnqueue) {
  auto k = ctx().program({"atomics.cl", "reduce.cl"}).kernel("sum_f32");
  cl::Buffer<float> in(ctx(), std::span<const float>(std::vector<float>(64, 1.0f)));
  cl::Buffer<float> total(ctx(), 1);
  total.fill(0.0f);
  cl::Buffer<unsigned> bad(ctx(), 1);
  bad.fill(0u);
  const std::uint64_t limit = ctx().device().local_mem_bytes;
  try {
    // Refused when the argument is set (before the driver sees it) or at the latest when launched.
    k.args(in, 64u, total, bad, cl::LocalMemory{std::size_t(limit) + 4});
    k.launch(64, 64);
    FAIL() << "a launch needing more __local memory than the device has was enqueued";
  } catch (const cl::Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("sum_f32"));
    EXPECT_THAT(e.what(), HasSubstr("__local"));
  }
  // The same kernel with what it needs runs.
  k.args(in, 64u, total, bad, cl::LocalMemory{64 * sizeof(float)});
  EXPECT_LE(k.local_mem_bytes(), limit);
  k.launch(64, 64);
  EXPECT_EQ(total.read()[0], 64.0f);
}

TEST_F(ClTest, OversizedBufferIsRefusedWithItsSize) {
  try {
    cl::Buffer<float> huge(ctx(), ctx().device().max_alloc_bytes / sizeof(float) + 1);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("max allocation"));
  }
}

TEST_F(ClTest, MemoryAccountingTracksPeak) {
  ctx().reset_peak();
  const auto base = ctx().bytes_in_use();
  {
    cl::Buffer<float> a(ctx(), 1000);
    cl::Buffer<float> b(ctx(), 500);
    EXPECT_EQ(ctx().bytes_in_use(), base + 6000);
  }
  EXPECT_EQ(ctx().bytes_in_use(), base);
  EXPECT_EQ(ctx().peak_bytes(), base + 6000);
}

}  // namespace
}  // namespace clr::test
