// The clradiosity binary as a user meets it: exit codes and one clear line on stderr.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "cl/device.hpp"
#include "image/image.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

using ::testing::HasSubstr;

TEST(Cli, VersionAndHelp) {
  auto r = run_cli("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.out, HasSubstr("clradiosity " CLR_VERSION));
  r = run_cli("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.out, HasSubstr("devices"));
}

TEST(Cli, UsageErrorsExitTwoWithOneLine) {
  for (const char* args : {"--no-such-flag", "no-such-command", "devices --json=maybe --bogus"}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
}

// Whatever a message quotes — a path, a value, a device spec — a 100 KB argument is not echoed whole.
TEST(Cli, AHugeArgumentIsNotEchoedWhole) {
  const std::string huge(50000, 'x');  // two of them stay below the kernel's limit on one argument (128 KiB)
  const std::string box = std::string(CLR_SOURCE_DIR) + "/scenes/cornell-box.xml";
  for (const std::string& args :
       {"devices --device " + huge, "train " + box + " --steps 1 --method " + huge + " -o /tmp/r",
        "render " + huge + ".xml --model r -o a.exr", "render " + box + " --model /tmp/" + huge + " -o a.exr",
        "compare " + huge + " " + huge, "train " + box + " --steps " + huge + " -o /tmp/r", "--" + huge}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args.substr(0, 60);
    EXPECT_LT(r.err.size(), 1024u) << args.substr(0, 60);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args.substr(0, 60);
  }
}

TEST(Cli, BadDeviceExitsTwoAndListsDevices) {
  const auto devices = cl::list_devices();
  if (devices.empty()) GTEST_SKIP() << "no OpenCL platform on this machine";
  for (const auto& [args, env] :
       {std::pair{"devices --device nosuch", ""}, std::pair{"devices", "CLRADIOSITY_DEVICE=nosuch"},
        std::pair{"devices --device 9:9", ""}}) {
    const auto r = run_cli(args, env);
    EXPECT_EQ(r.exit_code, 2) << args << " " << env;
    EXPECT_THAT(r.err, HasSubstr("available"));
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const auto& d : devices) EXPECT_THAT(r.err, HasSubstr(d.name));
  }
}

// No platform at all is the machine's fault, not the command's: exit 1 with the cause named — an ICD folder that
// registers no driver, or PoCL's unusable cache folder (PoCL then registers no platform and looks uninstalled).
TEST(Cli, NoPlatformExitsOneNamingTheCause) {
  const auto empty = std::filesystem::temp_directory_path() / ("clr_no_icd_" + std::to_string(::getpid()));
  std::filesystem::create_directories(empty);
  const std::pair<std::string, std::string> cases[] = {
      {"OCL_ICD_VENDORS=" + empty.string(), "OCL_ICD_VENDORS=" + empty.string() + " registers no driver"},
      {"OCL_ICD_VENDORS=" + (empty / "missing").string(), "does not exist"}};
  for (const auto& [env, cause] : cases)
    for (const char* args : {"devices", "devices --device cpu"}) {
      const auto r = run_cli(args, env);
      EXPECT_EQ(r.exit_code, 1) << args << " " << env << ": " << r.err;
      EXPECT_THAT(r.err, HasSubstr(cause)) << args << " " << env;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
  std::filesystem::remove_all(empty);

  // PoCL alone on this machine: its cache folder, made unusable, is named as the cause.
  const auto devices = cl::list_devices();
  if (devices.empty() || std::any_of(devices.begin(), devices.end(), [](const cl::DeviceInfo& d) {
        return d.platform_name.find("Portable Computing Language") == std::string::npos;
      }))
    GTEST_SKIP() << "a platform other than PoCL is present";
  const auto r = run_cli("devices", "POCL_CACHE_DIR=/proc/clr_no_such_folder");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("PoCL's kernel cache folder is not usable"));
  EXPECT_THAT(r.err, HasSubstr("/proc/clr_no_such_folder"));
}

TEST(Cli, DevicesListsEveryDeviceAndMarksTheDefault) {
  const auto devices = cl::list_devices();
  if (devices.empty()) GTEST_SKIP() << "no OpenCL platform on this machine";
  auto r = run_cli("devices");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto& d : devices) EXPECT_THAT(r.out, HasSubstr(d.describe()));
  EXPECT_THAT(r.out, HasSubstr("* " + cl::select_device(devices, "").describe()));

  r = run_cli("devices --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.size(), devices.size());
  for (std::size_t i = 0; i < devices.size(); ++i) {
    EXPECT_EQ(j[i]["name"], devices[i].name);
    EXPECT_EQ(j[i]["index"], devices[i].spec());
    EXPECT_EQ(j[i]["max_alloc_bytes"], devices[i].max_alloc_bytes);
    EXPECT_TRUE(j[i].contains("float_atomics") && j[i].contains("fp16") && j[i].contains("compute_units"));
  }

  r = run_cli("devices --json --device " + devices.back().spec());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).size(), 1u);
}

// --threads N / CLRADIOSITY_THREADS on every computing command: impossible values are refused naming the flag or
// the variable; the count changes how fast, never what: a reference renders byte for byte the same on one thread.
TEST(Cli, ThreadCountIsCheckedAndChangesNoResult) {
  const std::string box = std::string(CLR_SOURCE_DIR) + "/scenes/cornell-box.xml";
  const std::string reference = "reference " + box + " --spp 8 --width 24 --height 24 -o ";
  for (const std::string& args :
       {reference + "/tmp/x.exr --threads 0", reference + "/tmp/x.exr --threads many",
        "train " + box + " --steps 1 -o /tmp/r --threads -3",
        "render " + box + " --model /tmp/none -o x.exr --threads 5000", std::string("--threads 0")}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_THAT(r.err, HasSubstr("--threads")) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
  for (const char* value : {"abc", "0", "2x", "99999"}) {
    const auto r = run_cli(reference + "/tmp/x.exr", std::string("CLRADIOSITY_THREADS=") + value);
    EXPECT_EQ(r.exit_code, 2) << value;
    EXPECT_THAT(r.err, HasSubstr("CLRADIOSITY_THREADS")) << value;
  }
  const auto dir = std::filesystem::temp_directory_path() / ("clr_threads_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto one = run_cli(reference + (dir / "one.exr").string() + " --threads 1");
  const auto env = run_cli(reference + (dir / "env.exr").string(), "CLRADIOSITY_THREADS=1");
  const auto all = run_cli(reference + (dir / "all.exr").string());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(env.exit_code, 0) << env.err;
  ASSERT_EQ(all.exit_code, 0) << all.err;
  // The pixels, not the files' bytes: the header records the command line and the render time.
  const auto pixels = [&](const char* name) { return image::read_exr(dir / name).rgb; };
  EXPECT_FALSE(pixels("all.exr").empty());
  EXPECT_EQ(pixels("one.exr"), pixels("all.exr"));
  EXPECT_EQ(pixels("env.exr"), pixels("all.exr"));
  std::filesystem::remove_all(dir);
}

// Every CLRADIOSITY_* variable is checked before any work, on every command that computes: one line naming it, exit
// 2, and nothing written (a bad step schedule was refused only once the run folder existed).
TEST(Cli, EnvironmentIsCheckedBeforeAnyOutput) {
  const std::string box = std::string(CLR_SOURCE_DIR) + "/scenes/cornell-box.xml";
  const auto dir = std::filesystem::temp_directory_path() / ("clr_environment_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "out").string();
  const std::pair<const char*, const char*> variables[] = {{"CLRADIOSITY_STEP_SCHEDULE", "fast"},
                                                           {"CLRADIOSITY_STEP_SCHEDULE", "Serial "},
                                                           {"CLRADIOSITY_KERNEL_DIR", "/nonexistent/kernels"},
                                                           {"CLRADIOSITY_KERNEL_WARNINGS", "yes"},
                                                           {"CLRADIOSITY_EMULATE_LIMITS", "amd"}};
  for (const auto& [name, value] : variables)
    for (const std::string& command :
         {"train " + box + " --steps 2 --batch 64 -o " + out, "reference " + box + " --spp 1 -o " + out + ".exr",
          "render " + box + " --model " + out + " -o " + out + ".exr", std::string("devices")}) {
      const auto r = run_cli(command, std::string(name) + "='" + value + "'");
      EXPECT_EQ(r.exit_code, 2) << name << "=" << value << " " << command << ": " << r.err;
      EXPECT_THAT(r.err, HasSubstr(name)) << command;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << command << ": " << r.err;
      EXPECT_FALSE(std::filesystem::exists(out)) << name << ": " << command << " left a run folder";
      EXPECT_FALSE(std::filesystem::exists(out + ".exr")) << name << ": " << command << " left an image";
    }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clr::test
