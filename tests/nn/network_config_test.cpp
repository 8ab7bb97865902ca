// The network's JSON config is validated entry by entry (InputError naming the entry), and a checkpoint cannot
// make the reader allocate more than the file holds.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "common/error.hpp"
#include "nn/checkpoint.hpp"
#include "nn/network.hpp"
#include "support/cl_fixture.hpp"

namespace clr::test {
namespace {

using ::testing::HasSubstr;

// The message of the InputError the patched default config raises ("" when it is accepted).
std::string error_of(const nlohmann::json& patch) {
  nlohmann::json j = nn::to_json(nn::NetworkConfig{});
  j.merge_patch(patch);
  try {
    nn::network_config_from_json(j);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(NetworkConfig, ImpossibleEntriesAreNamed) {
  EXPECT_EQ(error_of(nlohmann::json::object()), "") << "the defaults are valid";
  const std::pair<nlohmann::json, const char*> cases[] = {
      {{{"adam", {{"learning_rate", -1}}}}, "'adam.learning_rate'"},
      {{{"adam", {{"learning_rate", 0}}}}, "'adam.learning_rate'"},
      {{{"adam", {{"learning_rate", 1e300}}}}, "'adam.learning_rate'"},  // inf once narrowed to float
      {{{"adam", {{"learning_rate", std::numeric_limits<double>::quiet_NaN()}}}}, "'adam.learning_rate'"},
      {{{"adam", {{"beta1", 1}}}}, "'adam.beta1'"},
      {{{"adam", {{"beta2", -0.5}}}}, "'adam.beta2'"},
      {{{"adam", {{"epsilon", 0}}}}, "'adam.epsilon'"},
      {{{"adam", {{"weight_decay", -1}}}}, "'adam.weight_decay'"},
      {{{"adam", {{"decay", 0}}}}, "'adam.decay'"},
      {{{"adam", {{"decay_interval", 0}}}}, "'adam.decay_interval'"},
      {{{"adam", {{"decay_start", -3}}}}, "'adam.decay_start'"},
      {{{"width", 0}}, "'width'"},
      {{{"width", -1}}, "'width'"},
      {{{"width", 2.5}}, "'width'"},
      {{{"width", 1 << 20}}, "'width'"},
      {{{"hidden_layers", 0}}, "'hidden_layers'"},
      {{{"outputs", 0}}, "'outputs'"},
      {{{"max_chunk_rows", 0}}, "'max_chunk_rows'"},
      {{{"encoder", {{"grid", {{"growth", 0.5}}}}}}, "'encoder.grid.growth'"},
      {{{"encoder", {{"grid", {{"levels", "many"}}}}}}, "'encoder.grid.levels'"},
      {{{"encoder", {{"grid", {{"bbox_lo", {0, 0, 2}}}}}}}, "'encoder.grid.bbox_hi'"},
      {{{"encoder", {{"grid", {{"dense_adam", 1}}}}}}, "'encoder.grid.dense_adam'"},
      {{{"encoder", {{"grid", {{"learning_rate_factor", 0}}}}}}, "'encoder.grid.learning_rate_factor'"},
      {{{"encoder", {{"grid", {{"learning_rate_factor", -2}}}}}}, "'encoder.grid.learning_rate_factor'"},
      {{{"encoder", {{"grid", {{"learning_rate_factor", std::numeric_limits<double>::quiet_NaN()}}}}}},
       "'encoder.grid.learning_rate_factor'"},
      {{{"encoder", {{"grid", {{"learning_rate_factor", 1e3}}}}}}, "'encoder.grid.learning_rate_factor'"},  // rate 5
      {{{"encoder", {{"grid", {{"learning_rate_factor", "4"}}}}}}, "'encoder.grid.learning_rate_factor'"},
      {{{"init", "xavier"}}, "'init'"},
      {{{"init", 1}}, "'init'"},
      {{{"albedo_factor", "yes"}}, "'albedo_factor'"},
  };
  for (const auto& [patch, name] : cases) EXPECT_THAT(error_of(patch), HasSubstr(name)) << patch.dump();
}

// The initialisation, the table's Adam and the albedo factor are written only where they differ from the defaults
// (configs written before they existed compare equal), and read back.
TEST(NetworkConfig, InitDenseAdamAndAlbedoFactorRoundTrip) {
  const nlohmann::json defaults = nn::to_json(nn::NetworkConfig{});
  EXPECT_FALSE(defaults.contains("init"));
  EXPECT_FALSE(defaults.contains("albedo_factor"));
  EXPECT_FALSE(defaults["encoder"]["grid"].contains("dense_adam"));
  EXPECT_FALSE(defaults["encoder"]["grid"].contains("learning_rate_factor"));
  EXPECT_EQ(error_of({{"init", "he"}, {"encoder", {{"grid", {{"dense_adam", false}, {"learning_rate_factor", 1}}}}}}),
            "")
      << "the defaults may be spelt out";
  nlohmann::json j = defaults;
  j.merge_patch({{"init", "torch"},
                 {"albedo_factor", true},
                 {"encoder", {{"grid", {{"dense_adam", true}, {"learning_rate_factor", 2.5}}}}}});
  const auto c = nn::network_config_from_json(j);
  EXPECT_EQ(c.init, nn::WeightInit::Torch);
  EXPECT_TRUE(c.encoder.grid->dense_adam);
  EXPECT_EQ(c.encoder.grid->learning_rate_factor, 2.5f);
  EXPECT_TRUE(c.albedo_factor);
  EXPECT_EQ(nn::to_json(c), j);
}

// A checkpoint whose checksum is right but whose tensor claims 2^62 floats: count · 4 wraps to 0, which a
// multiplied bound check lets through to a vector of 2^62 floats.
TEST(NetworkConfig, CheckpointTensorCountCannotWrapTheBoundCheck) {
  std::string payload;
  auto put = [&](auto v) { payload.append(reinterpret_cast<const char*>(&v), sizeof v); };
  auto put_str = [&](const std::string& s) {
    put(std::uint64_t(s.size()));
    payload += s;
  };
  put_str("{}");
  put(std::uint64_t(0));
  put_str("");
  put(std::uint32_t(1));
  put_str("mlp.params");
  put(std::uint64_t(1) << 62);
  std::string file("CLRCKPT\n", 8);
  const std::uint32_t version = nn::kCheckpointVersion, reserved = 0;
  const std::uint64_t size = payload.size(), sum = nn::fnv1a64(payload.data(), payload.size());
  for (const auto* p : {static_cast<const void*>(&version), static_cast<const void*>(&reserved)})
    file.append(static_cast<const char*>(p), 4);
  for (const auto* p : {&size, &sum}) file.append(reinterpret_cast<const char*>(p), 8);
  file += payload;
  const auto path = std::filesystem::temp_directory_path() / ("clr_wrap_" + std::to_string(::getpid()) + ".clr");
  std::ofstream(path, std::ios::binary) << file;
  try {
    nn::read_checkpoint(path.string());
    ADD_FAILURE() << "a tensor larger than the file was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("truncated payload while reading tensor values"));
  }
  std::filesystem::remove(path);
}

// Documented sentinels survive a patch: `encoder.grid: null` is "no hash grid" (not RFC 7396's "remove the key",
// which brought back a default grid over the unit cube), and a patch of the grid keeps the scene's box.
TEST(NetworkConfig, NullGridInAPatchMeansNoGrid) {
  nn::NetworkConfig base;
  base.encoder.grid->bbox_lo = {-5, -6, -7};
  base.encoder.grid->bbox_hi = {5, 6, 7};
  EXPECT_FALSE(nn::merge_patch(base, {{"encoder", {{"grid", nullptr}}}}).encoder.grid);
  const auto levels = nn::merge_patch(base, {{"encoder", {{"grid", {{"levels", 4}}}}}});
  ASSERT_TRUE(levels.encoder.grid);
  EXPECT_EQ(levels.encoder.grid->levels, 4);
  EXPECT_EQ(levels.encoder.grid->bbox_lo, base.encoder.grid->bbox_lo) << "the scene's box survives the patch";
  EXPECT_EQ(levels.encoder.grid->bbox_hi, base.encoder.grid->bbox_hi);
  // The guide's patch too (the other module), and no patch that removes a grid by accident.
  EXPECT_FALSE(nn::merge_patch(nn::NetworkConfig{}, {{"encoder", {{"grid", nullptr}, {"albedo", true}}}}).encoder.grid);
  // Any other null would silently restore a default (a scene-derived box among them): refused, named.
  for (const auto& [patch, name] : std::vector<std::pair<nlohmann::json, const char*>>{
           {{{"width", nullptr}}, "'width' is null"},
           {{{"encoder", nullptr}}, "'encoder' is null"},
           {{{"encoder", {{"grid", {{"bbox_lo", nullptr}}}}}}, "'encoder.grid.bbox_lo' is null"},
           {{{"adam", {{"learning_rate", nullptr}}}}, "'adam.learning_rate' is null"}}) {
    try {
      nn::merge_patch(base, patch);
      ADD_FAILURE() << patch.dump() << " was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(name));
    }
  }
  EXPECT_THROW(nn::network_config_from_json(nlohmann::json::array({1, 2})), InputError) << "not an object";
}

// Non-finite weights are named when a checkpoint's tensors are taken, whichever tensor holds them.
TEST(NetworkConfig, NonFiniteCheckpointTensorsAreRefused) {
  nn::Checkpoint c;
  for (const char* name : {"mlp.params", "grid.table", "guide.mlp.adam.v"})
    c.tensors.emplace_back(name, std::vector<float>(16, 0.25f));
  EXPECT_NO_THROW(c.tensor("m.clr", "mlp.params", 16));
  c.tensors[1].second[7] = std::numeric_limits<float>::quiet_NaN();
  c.tensors[2].second[15] = -std::numeric_limits<float>::infinity();
  for (const auto& [name, index] : {std::pair{"grid.table", "index 7"}, std::pair{"guide.mlp.adam.v", "index 15"}}) {
    try {
      c.tensor("m.clr", name, 16);
      ADD_FAILURE() << name << " with a non-finite value was taken";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(std::string("tensor '") + name + "' holds a non-finite value"));
      EXPECT_THAT(e.what(), HasSubstr(index));
    }
  }
}

TEST_F(ClTest, ParameterCountsWithoutBuildingMatchTheNetwork) {
  nn::NetworkConfig c;
  c.encoder.grid->levels = 4;
  c.encoder.grid->log2_table = 10;
  c.width = 16;
  c.hidden_layers = 2;
  c.outputs = 3;
  c.gemm = nn::GemmChoice::Own;
  for (bool albedo : {false, true}) {
    c.encoder.albedo = albedo;
    const nn::Network net(ctx(), c);
    EXPECT_EQ(nn::mlp_parameter_count(c) + nn::grid_parameter_count(c), net.parameter_count());
  }
  c.encoder.grid.reset();
  const nn::Network net(ctx(), c);
  EXPECT_EQ(nn::grid_parameter_count(c), 0u);
  EXPECT_EQ(nn::mlp_parameter_count(c), net.parameter_count());
}

}  // namespace
}  // namespace clr::test
