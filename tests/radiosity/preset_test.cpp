// Budget presets: their choices per device and scene size, and that flags-free runs get the preset's budget.
#include "radiosity/preset.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/error.hpp"
#include "radiosity/trainer.hpp"

namespace clr::radiosity {
namespace {

SceneInputs unit_box(double area) { return {{0, 0, 0}, {1, 1, 1}, false, false, area}; }

cl::DeviceInfo device_of(cl::DeviceType type) {
  cl::DeviceInfo d;
  d.type = type;
  return d;
}

TEST(Preset, BatchFollowsTheBudgetOnCpus) {
  std::map<std::string, TrainConfig> cpu, gpu;
  for (const char* name : {"preview", "balanced", "quality"}) {
    apply_preset(name, cpu[name], unit_box(6), device_of(cl::DeviceType::Cpu));
    apply_preset(name, gpu[name], unit_box(6), device_of(cl::DeviceType::Gpu));
    EXPECT_EQ(cpu[name].preset, name);
    EXPECT_EQ(gpu[name].batch, default_batch(device_of(cl::DeviceType::Gpu)))
        << name << ": GPUs keep the paper's batch";
    EXPECT_EQ(cpu[name].network["width"], default_width(device_of(cl::DeviceType::Cpu))) << name;
    EXPECT_EQ(gpu[name].network["width"], default_width(device_of(cl::DeviceType::Gpu))) << name;
  }
  EXPECT_LT(cpu["preview"].batch, cpu["balanced"].batch) << "a short budget takes more, smaller steps";
  EXPECT_EQ(cpu["balanced"].batch, default_batch(device_of(cl::DeviceType::Cpu))) << "balanced is the defaults";
  EXPECT_EQ(cpu["quality"].batch, default_batch(device_of(cl::DeviceType::Cpu)));
}

TEST(Preset, TableShrinksToWhatTheSurfacesTouch) {
  const auto table = [](double area) {
    TrainConfig c;
    apply_preset("balanced", c, unit_box(area), device_of(cl::DeviceType::Cpu));
    return c.network["encoder"]["grid"]["log2_table"].get<std::size_t>();
  };
  EXPECT_EQ(table(6.0), 18u) << "a box's six walls touch far more finest-level vertices than 2^18";
  EXPECT_LT(table(1e-4), 18u) << "a small object in a large empty box needs fewer entries";
  EXPECT_GE(table(1e-12), 10u);
}

TEST(Preset, GivesABudgetOnlyWhereNoneWasGiven) {
  TrainConfig none, steps, minutes;
  steps.steps = 7;
  minutes.minutes = 0.5;
  const auto why = apply_preset("quality", none, unit_box(6), device_of(cl::DeviceType::Cpu));
  apply_preset("quality", steps, unit_box(6), device_of(cl::DeviceType::Cpu));
  apply_preset("quality", minutes, unit_box(6), device_of(cl::DeviceType::Cpu));
  EXPECT_GT(none.minutes, 0.0);
  EXPECT_THAT(why.front(), ::testing::HasSubstr("budget"));
  EXPECT_EQ(steps.minutes, 0.0);
  EXPECT_EQ(steps.steps, 7);
  EXPECT_EQ(minutes.minutes, 0.5);
  EXPECT_THROW(apply_preset("fast", none, unit_box(6), device_of(cl::DeviceType::Cpu)), InputError);
}

// `paper` is the paper's settings on every device (ISNR §4.3, §5.1; docs/presets.md), not a budget class.
TEST(Preset, PaperTakesThePapersSettingsOnEveryDevice) {
  for (const auto type : {cl::DeviceType::Cpu, cl::DeviceType::Gpu}) {
    TrainConfig c;
    const auto why = apply_preset(kPaperPreset, c, unit_box(6), device_of(type));
    EXPECT_EQ(c.preset, kPaperPreset);
    EXPECT_EQ(c.network["width"], 512) << "§4.3: width 512, whatever the device's default";
    EXPECT_EQ(c.samples, 4) << "Table 1's N";
    EXPECT_DOUBLE_EQ(c.network["adam"]["learning_rate"].get<double>(), 0.005);
    EXPECT_DOUBLE_EQ(c.guide["adam"]["learning_rate"].get<double>(), 0.005);
    EXPECT_EQ(c.batch, default_batch(device_of(cl::DeviceType::Gpu))) << "the batch a GPU takes by default";
    const auto& grid = c.network["encoder"]["grid"];
    EXPECT_EQ(grid["levels"], 16);
    EXPECT_EQ(grid["log2_table"], 19);
    // The finest level at the cited work's N_max: N_min · b^(L−1).
    EXPECT_NEAR(grid["base_resolution"].get<double>() * std::pow(grid["growth"].get<double>(), 15.0), 2048, 1e-6);
    EXPECT_GT(c.steps, 0) << "a step budget where none was given";
    EXPECT_EQ(c.average_steps, 0) << "the network trained is the one rendered";
    EXPECT_THAT(why.back(), ::testing::HasSubstr("no parameters")) << "says what the paper leaves open";
    // The settings are valid as a whole (a config file with them is accepted).
    EXPECT_NO_THROW(c.validate());
  }
  TrainConfig given;
  given.steps = 300;
  apply_preset(kPaperPreset, given, unit_box(6), device_of(cl::DeviceType::Cpu));
  EXPECT_EQ(given.steps, 300);
  EXPECT_EQ(std::count(budget_preset_names().begin(), budget_preset_names().end(), kPaperPreset), 0)
      << "the main job's presets are budgets; the paper's settings would take hours on a CPU";
  EXPECT_EQ(std::count(preset_names().begin(), preset_names().end(), kPaperPreset), 1);
}

}  // namespace
}  // namespace clr::radiosity
