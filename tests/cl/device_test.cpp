// Device enumeration and the --device SPEC rule. The selection rule is tested on made-up device lists, so it
// runs everywhere; enumeration itself needs a real platform (PoCL in CI).
#include "cl/device.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

#include "common/error.hpp"

namespace clr::cl {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

DeviceInfo fake(unsigned p, unsigned d, std::string platform, std::string name, DeviceType type) {
  DeviceInfo info;
  info.platform_vendor = p == 0 ? "The pocl project" : "NVIDIA Corporation";
  info.platform_index = p;
  info.device_index = d;
  info.platform_name = std::move(platform);
  info.name = std::move(name);
  info.type = type;
  info.device = reinterpret_cast<cl_device_id>(std::uintptr_t(100 * p + d + 1));
  return info;
}

class DeviceSpecTest : public ::testing::Test {
 protected:
  // The variable is restored, not cleared: a test lane may set it (the Oclgrind lane names its simulator), and
  // the shared test context may be created after these tests ran.
  void SetUp() override {
    if (const char* env = std::getenv("CLRADIOSITY_DEVICE")) saved_ = env;
    unsetenv("CLRADIOSITY_DEVICE");
  }
  void TearDown() override {
    if (saved_)
      setenv("CLRADIOSITY_DEVICE", saved_->c_str(), 1);
    else
      unsetenv("CLRADIOSITY_DEVICE");
  }
  std::optional<std::string> saved_;
  std::vector<DeviceInfo> devices = {fake(0, 0, "Portable Computing Language", "pthread-skylake", DeviceType::Cpu),
                                     fake(1, 0, "NVIDIA CUDA", "NVIDIA H100 80GB HBM3", DeviceType::Gpu),
                                     fake(1, 1, "NVIDIA CUDA", "NVIDIA A100", DeviceType::Gpu)};
};

TEST_F(DeviceSpecTest, DefaultPrefersFirstGpu) { EXPECT_EQ(select_device(devices, "").spec(), "1:0"); }

TEST_F(DeviceSpecTest, DefaultFallsBackToCpu) {
  devices.resize(1);
  EXPECT_EQ(select_device(devices, "").spec(), "0:0");
}

TEST_F(DeviceSpecTest, IndicesSelectExactly) {
  EXPECT_EQ(select_device(devices, "1:1").name, "NVIDIA A100");
  EXPECT_EQ(select_device(devices, "0:0").type, DeviceType::Cpu);
}

TEST_F(DeviceSpecTest, SubstringMatches) {
  EXPECT_EQ(select_device(devices, "portable").spec(), "0:0");
  EXPECT_EQ(select_device(devices, "PoCL").spec(), "0:0") << "the vendor counts, not only the platform name";
  EXPECT_EQ(select_device(devices, "nvidia").spec(), "1:0");
  EXPECT_EQ(select_device(devices, "CPU").spec(), "0:0");
  EXPECT_EQ(select_device(devices, "gpu").spec(), "1:0");
  EXPECT_EQ(select_device(devices, "a100").spec(), "1:1");
}

TEST_F(DeviceSpecTest, RanksTakeTheMatchingDevicesRoundRobin) {
  // An MPI rank passes its local rank: the default rule's GPUs in turn, a substring's matches in turn, and a
  // P:D spec pins every rank to one device.
  EXPECT_EQ(select_device(devices, "", 0).spec(), "1:0");
  EXPECT_EQ(select_device(devices, "", 1).spec(), "1:1");
  EXPECT_EQ(select_device(devices, "", 2).spec(), "1:0");
  EXPECT_EQ(select_device(devices, "nvidia", 3).spec(), "1:1");
  EXPECT_EQ(select_device(devices, "cpu", 1).spec(), "0:0");
  EXPECT_EQ(select_device(devices, "1:0", 1).spec(), "1:0");
}

TEST_F(DeviceSpecTest, EnvironmentIsTheDefaultAndFlagWins) {
  setenv("CLRADIOSITY_DEVICE", "a100", 1);
  EXPECT_EQ(select_device(devices, "").spec(), "1:1");
  EXPECT_EQ(select_device(devices, "cpu").spec(), "0:0");
}

TEST_F(DeviceSpecTest, BadSpecsNameTheSpecAndListDevices) {
  for (const std::string bad : {"nosuch", "2:0", "0:7", "1:", ":1", "0:0x"}) {
    try {
      select_device(devices, bad);
      ADD_FAILURE() << "spec '" << bad << "' was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), AllOf(HasSubstr("'" + bad + "'"), HasSubstr("available"), HasSubstr("1:1"),
                                  HasSubstr("NVIDIA A100")));
    }
  }
}

TEST_F(DeviceSpecTest, BadEnvironmentSpecNamesTheVariable) {
  setenv("CLRADIOSITY_DEVICE", "nosuch", 1);
  EXPECT_THROW(
      {
        try {
          select_device(devices, "");
        } catch (const InputError& e) {
          EXPECT_THAT(e.what(), HasSubstr("CLRADIOSITY_DEVICE"));
          throw;
        }
      },
      InputError);
}

// No device at all is the machine's state, not the user's input: a runtime error (exit 1) that says why.
TEST_F(DeviceSpecTest, NoDevicesIsTheMachinesFailure) {
  for (const char* spec : {"", "cpu", "0:0"}) {
    try {
      select_device({}, spec);
      ADD_FAILURE() << spec << ": a device was selected from none";
    } catch (const InputError&) {
      ADD_FAILURE() << spec << ": reported as bad input";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("no OpenCL platform"), std::string::npos) << e.what();
    }
  }
}

TEST_F(DeviceSpecTest, DefaultNeverPicksASimulator) {
  // Oclgrind reports itself as a GPU; listed first, it must still lose to the real CPU.
  auto sim = fake(2, 0, "Oclgrind", "Oclgrind Simulator", DeviceType::Gpu);
  sim.simulator = true;
  std::vector<DeviceInfo> with_sim = {sim, devices[0]};
  EXPECT_EQ(select_device(with_sim, "").spec(), "0:0");
  EXPECT_EQ(select_device(with_sim, "", 1).spec(), "0:0") << "round-robin over real devices only";
  EXPECT_EQ(select_device(with_sim, "oclgrind").spec(), "2:0") << "naming it selects it";
  try {
    select_device({sim}, "");
    ADD_FAILURE() << "the simulator alone was picked by default";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("simulator"), HasSubstr("Oclgrind")));
  }
}

TEST(DeviceLimits, NvidiaEmulationClampsWhatTheDeviceReports) {
  DeviceInfo d = fake(0, 0, "Portable Computing Language", "pthread-skylake", DeviceType::Cpu);
  d.max_work_group_size = 4096;
  d.local_mem_bytes = 4u << 20;
  d.global_mem_bytes = 16ull << 30;
  d.max_alloc_bytes = 8ull << 30;
  d.fp16 = d.float_atomics = d.sub_groups = d.int64_atomics = true;
  emulate_nvidia_limits(d);
  EXPECT_EQ(d.max_work_group_size, 1024u);
  EXPECT_EQ(d.local_mem_bytes, 48u * 1024u);
  EXPECT_EQ(d.max_alloc_bytes, 4ull << 30);
  EXPECT_FALSE(d.fp16);
  EXPECT_FALSE(d.float_atomics);
  EXPECT_FALSE(d.sub_groups);
  EXPECT_TRUE(d.int64_atomics) << "NVIDIA has cl_khr_int64_base_atomics";
  EXPECT_THAT(d.describe(), HasSubstr("[nvidia limits]"));
  // Smaller figures stay as they are: emulation only clamps.
  DeviceInfo small = fake(0, 0, "p", "n", DeviceType::Cpu);
  small.max_work_group_size = 256;
  small.local_mem_bytes = 32 * 1024;
  small.global_mem_bytes = 1ull << 30;
  small.max_alloc_bytes = 128ull << 20;
  emulate_nvidia_limits(small);
  EXPECT_EQ(small.max_work_group_size, 256u);
  EXPECT_EQ(small.local_mem_bytes, 32u * 1024u);
  EXPECT_EQ(small.max_alloc_bytes, 128ull << 20);
}

TEST(DeviceLimits, UnknownEmulationIsAnInputError) {
  const char* before = std::getenv("CLRADIOSITY_EMULATE_LIMITS");
  const std::optional<std::string> saved = before ? std::optional<std::string>(before) : std::nullopt;
  setenv("CLRADIOSITY_EMULATE_LIMITS", "amd", 1);
  EXPECT_THROW(list_devices(), InputError);
  if (saved)
    setenv("CLRADIOSITY_EMULATE_LIMITS", saved->c_str(), 1);
  else
    unsetenv("CLRADIOSITY_EMULATE_LIMITS");
}

TEST(DeviceList, EnumeratesRealDevices) {
  const auto devices = list_devices();
  if (devices.empty()) GTEST_SKIP() << "no OpenCL platform on this machine";
  for (const auto& d : devices) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_GT(d.compute_units, 0u);
    EXPECT_GT(d.max_alloc_bytes, 0u);
    EXPECT_LE(d.max_alloc_bytes, d.global_mem_bytes);
    EXPECT_THAT(d.opencl_c_version, HasSubstr("OpenCL C"));
    EXPECT_GT(d.max_work_group_size, 0u);
    EXPECT_GT(d.local_mem_bytes, 0u);
    if (d.emulated == "nvidia") {
      EXPECT_LE(d.max_work_group_size, 1024u);
      EXPECT_LE(d.local_mem_bytes, 48u * 1024u);
      EXPECT_LE(d.max_alloc_bytes, d.global_mem_bytes / 4);
    }
    EXPECT_EQ(select_device(devices, d.spec()).device, d.device);
  }
}

}  // namespace
}  // namespace clr::cl
