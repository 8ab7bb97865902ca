// Budget presets: their choices per device and scene size, and that flags-free runs get the preset's budget.
#include "radiosity/preset.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "radiosity/trainer.hpp"

namespace clr::radiosity {
namespace {

SceneInputs unit_box(double area) { return {{0, 0, 0}, {1, 1, 1}, false, false, area}; }

cl::DeviceInfo device_of(const std::string& type) {
  cl::DeviceInfo d;
  d.type = type;
  return d;
}

TEST(Preset, WidthFollowsTheBudgetAndTheDevice) {
  std::size_t width[2][3];
  const char* names[] = {"preview", "balanced", "quality"};
  for (int gpu = 0; gpu < 2; ++gpu)
    for (int p = 0; p < 3; ++p) {
      TrainConfig c;
      apply_preset(names[p], c, unit_box(6), device_of(gpu ? "gpu" : "cpu"));
      EXPECT_EQ(c.preset, names[p]);
      EXPECT_EQ(c.batch, default_batch(device_of(gpu ? "gpu" : "cpu")));
      width[gpu][p] = c.network["width"].get<std::size_t>();
    }
  EXPECT_LT(width[0][0], width[0][1]) << "a preview takes the narrower, faster network";
  EXPECT_EQ(width[0][1], default_width(device_of("cpu"))) << "balanced is the defaults";
  EXPECT_EQ(width[1][1], default_width(device_of("gpu")));
  for (int p = 0; p < 3; ++p) EXPECT_LE(width[0][p], width[1][p]) << names[p] << ": a GPU never gets less";
}

TEST(Preset, TableShrinksToWhatTheSurfacesTouch) {
  const auto table = [](double area) {
    TrainConfig c;
    apply_preset("balanced", c, unit_box(area), device_of("cpu"));
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
  const auto why = apply_preset("quality", none, unit_box(6), device_of("cpu"));
  apply_preset("quality", steps, unit_box(6), device_of("cpu"));
  apply_preset("quality", minutes, unit_box(6), device_of("cpu"));
  EXPECT_GT(none.minutes, 0.0);
  EXPECT_THAT(why.front(), ::testing::HasSubstr("budget"));
  EXPECT_EQ(steps.minutes, 0.0);
  EXPECT_EQ(steps.steps, 7);
  EXPECT_EQ(minutes.minutes, 0.5);
  EXPECT_THROW(apply_preset("fast", none, unit_box(6), device_of("cpu")), InputError);
}

}  // namespace
}  // namespace clr::radiosity
