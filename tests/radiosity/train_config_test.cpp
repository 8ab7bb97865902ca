#include "radiosity/train_config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.hpp"

namespace clr::radiosity {
namespace {

using ::testing::HasSubstr;

std::string error_of(const nlohmann::json& j) {
  try {
    parse_train_config(j);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TrainConfig, JsonRoundTripKeepsEveryField) {
  TrainConfig c;
  c.samples = 32;
  c.batch = 1024;
  c.minutes = 2.5;
  c.seed = 99;
  c.network = {{"width", 128}};
  const TrainConfig back = parse_train_config(nlohmann::json(c));
  EXPECT_EQ(nlohmann::json(back), nlohmann::json(c));
  EXPECT_EQ(back.samples, 32);
  EXPECT_EQ(back.network["width"], 128);
}

TEST(TrainConfig, ImpossibleSettingsNameTheKey) {
  EXPECT_EQ(error_of(nlohmann::json::object()), "");
  EXPECT_THAT(error_of({{"samples", 0}}), HasSubstr("samples"));
  EXPECT_THAT(error_of({{"method", "pt"}}), HasSubstr("method"));
  EXPECT_EQ(error_of({{"method", "isnr"}}), "");
  EXPECT_THAT(error_of({{"is_loss", "js"}}), HasSubstr("is_loss"));
  EXPECT_THAT(error_of({{"bsdf_fraction", 0}}), HasSubstr("bsdf_fraction"));
  EXPECT_THAT(error_of({{"bsdf_fraction", 1.5}}), HasSubstr("bsdf_fraction"));
  EXPECT_THAT(error_of({{"guide", 3}}), HasSubstr("guide"));
  EXPECT_THAT(error_of({{"batch", -1}}), HasSubstr("batch"));
  EXPECT_THAT(error_of({{"samlpes", 4}}), HasSubstr("unknown training config key 'samlpes'"));
  EXPECT_THAT(error_of({{"samples", "four"}}), HasSubstr("should be a number"));
  EXPECT_THAT(error_of({{"samples", 4.5}}), HasSubstr("'samples'"));
  EXPECT_EQ(error_of({{"minutes", 3}}), "") << "an integer is a fine value for a real-valued key";
}

TEST(TrainConfig, LearningRateAnnealsGeometricallyOverTheBudget) {
  TrainConfig c;
  c.anneal_start = 0.5;
  c.anneal_final = 0.01;
  EXPECT_EQ(c.learning_rate_scale(0.0, 10000), 1.0);
  EXPECT_EQ(c.learning_rate_scale(0.5, 10000), 1.0);
  EXPECT_NEAR(c.learning_rate_scale(0.75, 10000), 0.1, 1e-12);
  EXPECT_NEAR(c.learning_rate_scale(1.0, 10000), 0.01, 1e-12);
  EXPECT_NEAR(c.learning_rate_scale(3.0, 10000), 0.01, 1e-12) << "past the budget the rate stays at its final value";
  c.anneal_start = 1.0;
  EXPECT_EQ(c.learning_rate_scale(1.0, 10000), 1.0) << "anneal_start 1 switches annealing off";
  EXPECT_THAT(error_of({{"anneal_final", 0}}), HasSubstr("anneal_final"));
  EXPECT_THAT(error_of({{"anneal_start", 1.5}}), HasSubstr("anneal_start"));
}

TEST(TrainConfig, LearningRateWarmsUpLinearlyOverItsSteps) {
  TrainConfig c;
  c.anneal_start = 0.5;
  c.anneal_final = 0.01;
  EXPECT_EQ(c.learning_rate_scale(0.0, 0), 1.0) << "no warm-up by default";
  c.learning_rate_warmup = 100;
  EXPECT_NEAR(c.learning_rate_scale(0.0, 0), 0.01, 1e-12) << "the first step takes a hundredth";
  EXPECT_NEAR(c.learning_rate_scale(0.0, 49), 0.5, 1e-12);
  EXPECT_EQ(c.learning_rate_scale(0.0, 99), 1.0);
  EXPECT_EQ(c.learning_rate_scale(0.0, 5000), 1.0);
  EXPECT_NEAR(c.learning_rate_scale(0.75, 49), 0.05, 1e-12) << "the warm-up multiplies the annealing";
  EXPECT_THAT(error_of({{"learning_rate_warmup", -1}}), HasSubstr("learning_rate_warmup"));
  EXPECT_THAT(error_of({{"learning_rate_warmup", 2.5}}), HasSubstr("learning_rate_warmup"));
}

TEST(TrainConfig, WeightAverageWarmsUpToItsTimeConstant) {
  TrainConfig c;
  c.average_steps = 100;
  EXPECT_NEAR(c.average_decay(0), 0.1, 1e-12) << "the first average is mostly the newest parameters";
  EXPECT_NEAR(c.average_decay(80), 81.0 / 90.0, 1e-12);
  EXPECT_NEAR(c.average_decay(5000), 0.99, 1e-12) << "then 1 - 1/average_steps";
  EXPECT_THAT(error_of({{"average_steps", -5}}), HasSubstr("average_steps"));
}

TEST(TrainConfig, RelativeResidualFadesToL2OverTheBudget) {
  TrainConfig c;
  EXPECT_EQ(c.relative_power(0.0), 0.5) << "the default ceiling";
  c.relative_power_max = 1.0;
  c.relative_fade_end = 0.8;
  EXPECT_EQ(c.relative_power(0.0), 1.0);
  EXPECT_NEAR(c.relative_power(0.4), 0.5, 1e-12);
  EXPECT_EQ(c.relative_power(0.8), 0.0);
  EXPECT_EQ(c.relative_power(1.5), 0.0) << "past the fade the residual stays plain L2";
  c.relative_fade_end = 0.0;
  EXPECT_EQ(c.relative_power(0.9), 1.0) << "relative_fade_end 0 keeps the relative residual";
  c.residual = Residual::L2;
  EXPECT_EQ(c.relative_power(0.0), 0.0);
  EXPECT_THAT(error_of({{"relative_fade_end", -0.1}}), HasSubstr("relative_fade_end"));
}

// relative_warmup: plain L2 first, the power rising to the fade's value over that fraction of the budget.
TEST(TrainConfig, RelativeResidualCanStartInL2) {
  TrainConfig c;
  c.relative_power_max = 1.0;
  c.relative_warmup = 0.2;
  EXPECT_EQ(c.relative_power(0.0), 0.0) << "the first step is plain L2";
  EXPECT_NEAR(c.relative_power(0.1), 0.5 * 0.9, 1e-12) << "half way up towards the fade's 0.9";
  EXPECT_NEAR(c.relative_power(0.2), 0.8, 1e-12) << "then the fade alone";
  EXPECT_NEAR(c.relative_power(0.6), 0.4, 1e-12);
  EXPECT_EQ(c.relative_power(1.0), 0.0);
  c.residual = Residual::L2;
  EXPECT_EQ(c.relative_power(0.3), 0.0);
  EXPECT_THAT(error_of({{"relative_warmup", 1.5}}), HasSubstr("relative_warmup"));
}

// relative_power_max: the whole schedule scaled below 1, so the relative residual never reaches its scale-free power.
TEST(TrainConfig, RelativePowerHasACeiling) {
  TrainConfig c;
  c.relative_power_max = 0.5;
  c.relative_fade_end = 1.0;
  c.relative_warmup = 0.0;
  EXPECT_EQ(c.relative_power(0.0), 0.5);
  EXPECT_NEAR(c.relative_power(0.5), 0.25, 1e-12);
  EXPECT_EQ(c.relative_power(1.0), 0.0);
  c.relative_warmup = 0.2;
  EXPECT_NEAR(c.relative_power(0.1), 0.5 * 0.5 * 0.9, 1e-12) << "the ramp and the fade under the ceiling";
  c.relative_power_max = 0.0;
  EXPECT_EQ(c.relative_power(0.5), 0.0) << "a ceiling of 0 is plain L2";
  EXPECT_THAT(error_of({{"relative_power_max", 1.5}}), HasSubstr("relative_power_max"));
  EXPECT_THAT(error_of({{"relative_power_max", -0.5}}), HasSubstr("in [0, 1]"));
}

TEST(TrainConfig, GuidedShareRampsInOverTheWarmUp) {
  TrainConfig c;
  c.bsdf_fraction = 0.4;
  c.guide_warmup = 0.2;
  EXPECT_EQ(c.bsdf_fraction_at(0.0), 1.0) << "nothing is drawn from the untrained guide";
  EXPECT_NEAR(c.bsdf_fraction_at(0.1), 0.7, 1e-12);
  EXPECT_EQ(c.bsdf_fraction_at(0.2), 0.4);
  EXPECT_EQ(c.bsdf_fraction_at(2.0), 0.4);
  c.guide_warmup = 0.0;
  EXPECT_EQ(c.bsdf_fraction_at(0.0), 0.4) << "guide_warmup 0 guides from the first step";
  EXPECT_THAT(error_of({{"guide_warmup", 1.5}}), HasSubstr("guide_warmup"));
}

TEST(TrainConfig, FileErrorsNameTheFile) {
  const auto path = std::filesystem::temp_directory_path() / "clr_bad_config.json";
  std::ofstream(path) << "{ \"samples\": 4,";
  try {
    load_train_config(path.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("clr_bad_config.json"));
  }
  std::filesystem::remove(path);
  EXPECT_THROW(load_train_config(path.string()), InputError);
}

}  // namespace
}  // namespace clr::radiosity
