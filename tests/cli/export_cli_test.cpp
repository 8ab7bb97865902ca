// `clradiosity export`: the safetensors file others open. The round trip that matters is a reader who has only the
// file: tests/cli/export_eval.py evaluates each network in numpy from the tensors and the metadata's description
// and must match the engine's own inference on the same raw rows.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>

#include "nn/checkpoint.hpp"
#include "nn/encoder.hpp"
#include "nn/safetensors.hpp"
#include "radiosity/run_directory.hpp"
#include "support/cl_fixture.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"
#include "support/test_python.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

// The fixture's small N-Module (4 levels, 2^12 entries) has dense coarse levels and a hashed finest one (the
// I-Module's defaults have both too); guide_lag 1 puts the lagged guide's copy in the checkpoint; no weight average, so
// that the exported N-Module is model.clr's parameters (ExportAveragedCli below exports an average).
class ExportCli : public CliRunDir {
 protected:
  ExportCli() : CliRunDir("export_cli", {{"guide_lag", 1}, {"average_steps", 0}}) {}

  // A short ISNR run with a high learning rate, so that the hash grids' entries move far from their ±1e-4 start
  // and an evaluation that got the grid wrong cannot pass.
  fs::path train() {
    const fs::path run = dir / "run";
    const auto r = run_cli("train " + kBox + " --steps 30 --learning-rate 0.05 --guide-learning-rate 0.05 --config " +
                           config + " -o " + run.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return run;
  }
};

void write_floats(const fs::path& path, const std::vector<float>& v) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * 4));
}

// Raw rows (nn/encoder.hpp) spread over the scene's box and a little past it (the grid clamps there), unit
// directions and normals, albedo and roughness in [0, 1].
std::vector<float> random_rows(std::size_t n) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  std::normal_distribution<float> g;
  std::vector<float> rows(n * nn::kRawInputs);
  for (std::size_t r = 0; r < n; ++r) {
    float* row = &rows[r * nn::kRawInputs];
    for (int i = 0; i < 3; ++i) row[nn::raw::kPosition + i] = -1.2f + 2.4f * u(rng) + (i == 1 ? 1.0f : 0.0f);
    for (const std::size_t at : {nn::raw::kDirection, nn::raw::kNormal}) {
      float d[3] = {g(rng), g(rng), g(rng)};
      const float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (int i = 0; i < 3; ++i) row[at + i] = d[i] / len;
    }
    for (int i = 0; i < 4; ++i) row[nn::raw::kAlbedo + i] = u(rng);
  }
  return rows;
}

// tests/cli/export_eval.py on network `name` of the safetensors file `model`: its exit status (0 when numpy's outputs
// for dir/rows.f32 match the engine's in dir/NAME.f32).
int numpy_evaluation(const std::string& py, const fs::path& model, const fs::path& dir, const std::string& name,
                     const std::string& flags = "") {
  return std::system(("'" + py + "' '" CLR_SOURCE_DIR "/tests/cli/export_eval.py' '" + model.string() + "' " + name +
                      " '" + (dir / "rows.f32").string() + "' '" + (dir / (name + ".f32")).string() + "' " + flags)
                         .c_str());
}

std::vector<float> infer(cl::Context& ctx, nn::Network& network, const std::vector<float>& rows) {
  const std::size_t n = rows.size() / nn::kRawInputs;
  cl::Buffer<float> in(ctx, std::span<const float>(rows)), out(ctx, n * network.outputs());
  network.infer(in, n, out);
  return out.read();
}

TEST_F(ExportCli, NumpyEvaluatesEveryNetworkAsTheEngineDoes) {
  const fs::path run = train();
  const fs::path model = dir / "model.safetensors";
  auto r = run_cli("export " + run.string() + " -o " + model.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  cl::Context* ctx = shared_context();
  if (!ctx) GTEST_SKIP() << "no OpenCL device";
  const std::string py = test_python();
  if (py.empty()) GTEST_SKIP() << "safetensors and numpy could not be installed into " CLR_PYTHON_VENV " (pip)";

  const auto rows = random_rows(384);
  write_floats(dir / "rows.f32", rows);
  auto radiance = radiosity::RunDirectory::load_radiance(*ctx, run);
  auto guide = radiosity::RunDirectory::load_guide(*ctx, run);
  auto before = radiosity::RunDirectory::load_guide_before(*ctx, run, guide->config());
  ASSERT_TRUE(before) << "guide_lag 1 should store the guide before its last update";
  const std::map<std::string, nn::Network*> networks = {
      {"n_module", radiance.get()}, {"i_module", guide.get()}, {"i_module_before_update", before.get()}};
  for (const auto& [name, network] : networks) {
    write_floats(dir / (name + ".f32"), infer(*ctx, *network, rows));
    EXPECT_EQ(numpy_evaluation(py, model, dir, name), 0)
        << name << ": numpy's evaluation differs from the engine's by more than 1e-5";
  }
  // The comparison sees the grid: without its features numpy's outputs are off.
  EXPECT_NE(numpy_evaluation(py, model, dir, "n_module", "--without-grid"), 0);
}

TEST_F(ExportCli, EveryTensorIsThereInItsLayout) {
  const fs::path run = train();
  const fs::path model = dir / "model.safetensors", weights = dir / "weights.safetensors";
  ASSERT_EQ(run_cli("export " + run.string() + " -o " + model.string()).exit_code, 0);
  ASSERT_EQ(run_cli("export " + (run / "model.clr").string() + " --weights-only -o " + weights.string()).exit_code, 0);
  const auto checkpoint = nn::read_checkpoint((run / "model.clr").string());
  const auto file = nn::read_safetensors(model);
  std::map<std::string, const nn::SafeTensor*> by_name;
  std::size_t exported = 0, stored = 0;
  for (const auto& t : file.tensors) by_name[t.name] = &t, exported += t.values.size();
  for (const auto& t : checkpoint.tensors) stored += t.second.size();
  EXPECT_EQ(exported, stored) << "every value of model.clr is exported, once";

  const auto stored_tensor = [&](const std::string& name) -> const std::vector<float>& {
    for (const auto& [n, v] : checkpoint.tensors)
      if (n == name) return v;
    throw std::runtime_error(name + " is not in model.clr");
  };
  // Weights as PyTorch's nn.Linear holds them ([outputs × inputs]); the engine stores [inputs × outputs].
  const auto& params = stored_tensor("mlp.params");
  const auto* w0 = by_name.at("mlp.layers.0.weight");
  ASSERT_EQ(w0->shape.size(), 2u);
  const std::size_t out = w0->shape[0], in = w0->shape[1];
  EXPECT_EQ(out, 32u);
  for (std::size_t o = 0; o < out; ++o)
    for (std::size_t i = 0; i < in; ++i) ASSERT_EQ(w0->values[o * in + i], params[i * out + o]) << o << "," << i;
  EXPECT_EQ(by_name.at("mlp.layers.0.bias")->values[3], params[in * out + 3]);
  // Levels follow each other in the table; the coarse ones dense, the first hashed one the table's size.
  const auto networks = nlohmann::json::parse(file.metadata.at("networks"));
  const auto& levels = networks.at("n_module").at("encoding").at(0).at("levels");
  EXPECT_EQ(levels.at(0).at("dense"), true);
  std::size_t hashed = 0, before = 0;
  while (hashed < levels.size() && levels.at(hashed).at("dense") == true)
    before += by_name.at("grid.levels." + std::to_string(hashed++))->values.size();
  ASSERT_LT(hashed, levels.size()) << "the finest levels are hashed";
  const auto& table = stored_tensor("grid.table");
  const auto& first_hashed = *by_name.at("grid.levels." + std::to_string(hashed));
  EXPECT_EQ(first_hashed.shape, (std::vector<std::uint64_t>{4096, 2}));
  EXPECT_EQ(first_hashed.values[5], table[before + 5]);
  for (const char* name : {"guide.mlp.layers.3.weight", "guide.grid.levels.3", "guide_before.mlp.layers.0.bias",
                           "adam.m.mlp.layers.1.weight", "guide.adam.v.grid.levels.0"})
    EXPECT_TRUE(by_name.contains(name)) << name;

  EXPECT_EQ(networks.at("n_module").at("mlp").back().at("activation"), "abs");
  EXPECT_EQ(file.metadata.at("step"), "30");
  EXPECT_TRUE(file.metadata.contains("train_config") && file.metadata.contains("scene"));

  for (const auto& t : nn::read_safetensors(weights).tensors)
    EXPECT_EQ(t.name.find("adam."), std::string::npos) << "--weights-only keeps " << t.name;
}

// A run with a weight average and the albedo factor: the N-Module exported is the average (what render draws),
// numpy evaluates it with the factor as the engine does, and the trained parameters follow as training.*.
class ExportAveragedCli : public CliRunDir {
 protected:
  ExportAveragedCli()
      : CliRunDir("export_avg_cli", {{"method", "nr"}, {"average_steps", 5}, {"network", {{"albedo_factor", true}}}}) {}
};

TEST_F(ExportAveragedCli, TheWeightAverageIsTheExportedModel) {
  const fs::path run = dir / "run", model = dir / "model.safetensors", weights = dir / "weights.safetensors";
  auto r = run_cli("train " + kBox + " --steps 30 --learning-rate 0.05 --config " + config + " -o " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(run_cli("export " + run.string() + " -o " + model.string()).exit_code, 0);
  ASSERT_EQ(run_cli("export " + run.string() + " --weights-only -o " + weights.string()).exit_code, 0);
  const auto checkpoint = nn::read_checkpoint((run / "model.clr").string());
  const auto stored = [&](const std::string& name) -> const std::vector<float>& {
    for (const auto& [n, v] : checkpoint.tensors)
      if (n == name) return v;
    throw std::runtime_error(name + " is not in model.clr");
  };
  const auto file = nn::read_safetensors(model);
  std::map<std::string, const nn::SafeTensor*> by_name;
  for (const auto& t : file.tensors) by_name[t.name] = &t;
  const auto* w0 = by_name.at("mlp.layers.0.weight");
  const std::size_t out = w0->shape[0], in = w0->shape[1];
  const auto& average = stored("mlp.average");
  EXPECT_NE(average, stored("mlp.params"));
  for (std::size_t o = 0; o < out; ++o)
    for (std::size_t i = 0; i < in; ++i) ASSERT_EQ(w0->values[o * in + i], average[i * out + o]) << o << "," << i;
  EXPECT_EQ(by_name.at("training.mlp.params")->values, stored("mlp.params"));
  EXPECT_EQ(by_name.at("training.grid.table")->values, stored("grid.table"));
  EXPECT_TRUE(file.metadata.contains("n_module_parameters"));
  for (const auto& t : nn::read_safetensors(weights).tensors)
    EXPECT_EQ(t.name.find("training."), std::string::npos) << "--weights-only keeps " << t.name;

  cl::Context* ctx = shared_context();
  if (!ctx) GTEST_SKIP() << "no OpenCL device";
  const std::string py = test_python();
  if (py.empty()) GTEST_SKIP() << "safetensors and numpy could not be installed into " CLR_PYTHON_VENV " (pip)";
  const auto rows = random_rows(384);
  write_floats(dir / "rows.f32", rows);
  auto radiance = radiosity::RunDirectory::load_radiance(*ctx, run);
  write_floats(dir / "n_module.f32", infer(*ctx, *radiance, rows));
  EXPECT_EQ(numpy_evaluation(py, model, dir, "n_module"), 0)
      << "numpy's evaluation of the averaged, albedo-factored model differs";
}

TEST_F(ExportCli, BadInputExitsTwoBeforeWriting) {
  const fs::path run = train();
  const auto refused = [&](const std::string& args, const std::string& fragment) {
    const auto r = run_cli("export " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(fragment)) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  };
  refused(run.string() + " -o " + (dir / "model.pt").string(), "must end in .safetensors");
  refused((dir / "nothing").string() + " -o " + (dir / "a.safetensors").string(), "nothing");
  std::ofstream(dir / "broken.clr") << "not a checkpoint";
  refused(run.string() + " -o " + (dir / "broken.clr" / "a.safetensors").string(), "a.safetensors");
  refused((dir / "broken.clr").string() + " -o " + (dir / "b.safetensors").string(), "broken.clr");
  // A checkpoint that names one tensor twice (its checksum intact): refused by every reader of checkpoints, export
  // and render among them, as bad input.
  nn::Checkpoint twice = nn::read_checkpoint((run / "model.clr").string());
  twice.tensors.push_back(twice.tensors.front());
  fs::create_directories(dir / "twice");
  for (const char* file : {"config.json", "scene.json", "log.csv"}) fs::copy_file(run / file, dir / "twice" / file);
  nn::write_checkpoint((dir / "twice" / "model.clr").string(), twice);
  refused((dir / "twice").string() + " -o " + (dir / "c.safetensors").string(), "appears twice");
  const auto r = run_cli("render " + kBox + " --model " + (dir / "twice").string() + " --width 8 --height 8 -o " +
                         (dir / "c.exr").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("appears twice"));
  for (const char* name : {"model.pt", "a.safetensors", "b.safetensors", "c.safetensors", "c.exr"})
    EXPECT_FALSE(fs::exists(dir / name)) << name;
}

}  // namespace
}  // namespace clr::test
