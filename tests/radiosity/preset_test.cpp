// Budget presets: their choices per device and scene size, and that flags-free runs get the preset's budget.
#include "radiosity/preset.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace clr::radiosity
