// train --reference / --preview as a user runs them (radiosity/convergence.hpp): the logged error is exactly what
// `compare` says of a `render` of the same checkpoint, evaluating changes nothing the run trains, a resumed run
// continues the columns (an older run's log gains them), and bad options are refused before any training.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "image/image.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// log.csv as rows of fields, keyed by the header's names.
struct Log {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  explicit Log(const fs::path& file) {
    std::istringstream in(text_of(file));
    std::string line;
    bool first = true;
    while (std::getline(in, line)) {
      std::vector<std::string> fields;
      std::stringstream s(line);
      std::string f;
      while (std::getline(s, f, ',')) fields.push_back(f);
      if (!line.empty() && line.back() == ',') fields.emplace_back();
      if (first)
        header = fields;
      else
        rows.push_back(fields);
      first = false;
    }
  }
  std::size_t column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << "no column " << name;
    return std::size_t(it - header.begin());
  }
  // The field `name` of the row logged at `step` ("" when there is none).
  std::string at(long step, const std::string& name) const {
    for (const auto& r : rows)
      if (r.at(0) == std::to_string(step)) return r.at(column(name));
    return "";
  }
};

class ConvergenceCli : public CliRunDir {
 protected:
  ConvergenceCli() : CliRunDir("convergence_cli") {}
  void SetUp() override {
    CliRunDir::SetUp();
    if (IsSkipped()) return;
    // A quarter of the bundled box's 128² film: the shape of the film, a quick render.
    reference = (dir / "ref.exr").string();
    const auto r = run_cli("reference " + kBox + " --spp 16 --width 32 --height 32 -o " + reference);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  std::string reference;
};

TEST_F(ConvergenceCli, LoggedErrorIsCompareOfARenderOfTheCheckpoint) {
  const fs::path run = dir / "run", preview = dir / "preview.png";
  auto r = run_cli("train " + kBox + " --steps 20 --config " + config + " --reference " + reference +
                   " --eval-every 10 --eval-spp 2 --preview " + preview.string() + " -o " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("convergence: "));
  EXPECT_THAT(r.out, HasSubstr("peak device memory: "));
  EXPECT_TRUE(fs::exists(preview));
  const std::string figure = text_of(run / "convergence.svg");
  EXPECT_THAT(figure, HasSubstr("<svg"));
  EXPECT_THAT(figure, HasSubstr("<polyline")) << "two evaluations make a line";

  const Log log(run / "log.csv");
  EXPECT_EQ(log.header.back(), "mean_ratio");
  EXPECT_EQ(log.at(5, "mape"), "") << "a row between evaluations leaves the columns empty";
  EXPECT_EQ(log.at(5, "mean_ratio"), "");
  EXPECT_NE(log.at(10, "mape"), "");
  for (const auto& row : log.rows) EXPECT_EQ(row.size(), log.header.size());

  // The checkpoint at step 20 is the model evaluated there: `render` it the same way and `compare`.
  const std::string image = (dir / "render.exr").string();
  r = run_cli("render " + kBox + " --model " + run.string() + " --width 32 --height 32 --spp 2 -o " + image);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("compare " + image + " " + reference + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = nlohmann::json::parse(r.out);
  EXPECT_EQ(std::stod(log.at(20, "mape")), m["mape"].get<double>());
  EXPECT_EQ(std::stod(log.at(20, "mse")), m["mse"].get<double>());
  EXPECT_EQ(std::stod(log.at(20, "relmse")), m["relmse"].get<double>());
  EXPECT_EQ(std::stod(log.at(20, "mean_ratio")), m["mean_ratio"].get<double>());
  EXPECT_NE(log.at(10, "mape"), log.at(20, "mape")) << "each evaluation is of the model at its step";

  // Evaluating is outside the training: the same run without it trains the same parameters, bit for bit.
  const fs::path plain = dir / "plain";
  r = run_cli("train " + kBox + " --steps 20 --config " + config + " -o " + plain.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(text_of(plain / "model.clr"), text_of(run / "model.clr"));
  EXPECT_FALSE(fs::exists(plain / "convergence.svg")) << "no evaluation, no figure";

  // So too where the next step's guided directions are drawn during this one (the lagged guide): an evaluation
  // between the two leaves them alone.
  auto lagged = nlohmann::json::parse(text_of(config));
  lagged["guide_lag"] = 1;
  const std::string lagged_config = (dir / "lagged.json").string();
  std::ofstream(lagged_config) << lagged.dump();
  for (const std::string& watch : {std::string(), " --reference " + reference + " --eval-every 3 --eval-spp 1"}) {
    r = run_cli("train " + kBox + " --steps 12 --config " + lagged_config + watch + " -o " +
                (dir / (watch.empty() ? "lag_plain" : "lag_watched")).string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_EQ(text_of(dir / "lag_plain" / "model.clr"), text_of(dir / "lag_watched" / "model.clr"));
}

TEST_F(ConvergenceCli, ResumedRunContinuesTheColumns) {
  const fs::path run = dir / "run";
  auto r = run_cli("train " + kBox + " --steps 10 --config " + config + " --reference " + reference +
                   " --eval-every 10 --eval-spp 2 -o " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Another spp would put two measures in one column: refused before training, nothing logged.
  const std::size_t rows_before = Log(run / "log.csv").rows.size();
  r = run_cli("train " + kBox + " --resume --steps 20 --reference " + reference + " --eval-spp 3 -o " + run.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--eval-spp"));
  EXPECT_EQ(Log(run / "log.csv").rows.size(), rows_before);
  // The run's own spp without --eval-spp; the evaluation at the last step of the resumed session too.
  r = run_cli("train " + kBox + " --resume --steps 25 --reference " + reference + " --eval-every 10 -o " +
              run.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Log log(run / "log.csv");
  EXPECT_NE(log.at(10, "mape"), "");
  EXPECT_NE(log.at(20, "mape"), "");
  EXPECT_NE(log.at(25, "mape"), "") << "the last step is evaluated";
  EXPECT_EQ(log.at(15, "mape"), "");
  EXPECT_EQ(nlohmann::json::parse(text_of(run / "evaluation.json"))["spp"], 2);
}

// The image mode is part of what the columns measure: a resumed rhs run keeps rhs without --eval-mode and refuses an
// lhs given (the record names the mode only where it is rhs); an lhs run refuses rhs.
TEST_F(ConvergenceCli, ResumedRunKeepsItsImageMode) {
  const fs::path rhs = dir / "rhs", lhs = dir / "lhs";
  auto r = run_cli("train " + kBox + " --steps 10 --config " + config + " --reference " + reference +
                   " --eval-every 10 --eval-spp 1 --eval-mode rhs -o " + rhs.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(text_of(rhs / "evaluation.json"))["mode"], "rhs");
  r = run_cli("train " + kBox + " --resume --steps 20 --reference " + reference + " --eval-mode lhs -o " +
              rhs.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--eval-mode"));
  r = run_cli("train " + kBox + " --resume --steps 20 --reference " + reference + " -o " + rhs.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(Log(rhs / "log.csv").at(20, "mape"), "");
  r = run_cli("train " + kBox + " --steps 10 --config " + config + " --reference " + reference +
              " --eval-every 10 --eval-spp 1 -o " + lhs.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("train " + kBox + " --resume --steps 20 --reference " + reference + " --eval-mode rhs -o " +
              lhs.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--eval-mode"));
  r = run_cli("train " + kBox + " --steps 10 --reference " + reference + " --eval-mode both -o " +
              (dir / "bad").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--eval-mode"));
}

// Logs of the three older shapes (before the evaluation columns, before the samples column, before the mean ratio)
// gain today's columns on resume: empty evaluations, and the samples each row's step had seen by the run's batch
// and N.
TEST_F(ConvergenceCli, OlderRunGainsTheColumnsOnResume) {
  for (const std::string cut : {",mape,mse,relmse,samples,mean_ratio", ",samples,mean_ratio", ",mean_ratio"}) {
    const fs::path run = dir / ("old" + std::to_string(cut.size()));
    auto r = run_cli("train " + kBox + " --steps 10 --config " + config + " -o " + run.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Log fresh(run / "log.csv");
    ASSERT_EQ(fresh.header.back(), "mean_ratio");
    const auto settings = nlohmann::json::parse(text_of(run / "config.json"));
    const long per_step = settings.at("batch").get<long>() * settings.at("samples").get<long>();
    EXPECT_EQ(fresh.at(10, "samples"), std::to_string(10 * per_step));
    // As a run from before those columns wrote it: the header and every row lose their last cells.
    const auto cells = std::count(cut.begin(), cut.end(), ',');
    std::string old;
    std::istringstream in(text_of(run / "log.csv"));
    for (std::string line; std::getline(in, line);) {
      std::size_t end = line.size();
      for (long k = 0; k < cells; ++k) end = line.rfind(',', end - 1);
      if (old.empty()) {
        ASSERT_EQ(line.substr(end), cut);
      }
      old += line.substr(0, end) + "\n";
    }
    std::ofstream(run / "log.csv") << old;
    r = run_cli("train " + kBox + " --resume --steps 20 --reference " + reference + " --eval-every 10 -o " +
                run.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Log upgraded(run / "log.csv");
    EXPECT_EQ(upgraded.header, fresh.header);
    for (const auto& row : upgraded.rows) EXPECT_EQ(row.size(), upgraded.header.size());
    EXPECT_EQ(upgraded.at(10, "mape"), "") << "the older session had no evaluation";
    EXPECT_NE(upgraded.at(20, "mape"), "");
    EXPECT_EQ(upgraded.at(10, "samples"), std::to_string(10 * per_step)) << "an older row's samples, restored";
    EXPECT_EQ(upgraded.at(20, "samples"), std::to_string(20 * per_step));
    EXPECT_EQ(upgraded.at(10, "mean_ratio"), "");
    const double ratio = std::stod(upgraded.at(20, "mean_ratio"));
    EXPECT_TRUE(ratio > 0 && std::isfinite(ratio)) << upgraded.at(20, "mean_ratio");
  }
}

TEST_F(ConvergenceCli, BadOptionsAreRefusedBeforeTraining) {
  const std::string wrong_shape = (dir / "wide.exr").string(), not_exr = (dir / "not.exr").string();
  ASSERT_EQ(run_cli("reference " + kBox + " --spp 1 --width 32 --height 16 -o " + wrong_shape).exit_code, 0);
  std::ofstream(not_exr) << "not an image";
  // A reference with nothing to measure against: every value NaN (or infinite).
  const std::string all_nan = (dir / "nan.exr").string();
  {
    image::Image nan_image(32, 32);
    std::fill(nan_image.rgb.begin(), nan_image.rgb.end(), std::nanf(""));
    nan_image.rgb[5] = INFINITY;
    image::write_exr(all_nan, nan_image);
  }
  const std::string x = (dir / "x").string(), train = "train " + kBox + " --steps 5 --config " + config + " ";
  const std::pair<std::string, std::string> cases[] = {
      {train + "--reference " + reference + " --eval-every 0 -o " + x, "--eval-every"},
      {train + "--reference " + reference + " --eval-every 2.5 -o " + x, "--eval-every"},
      {train + "--reference " + reference + " --eval-spp 0 -o " + x, "--eval-spp"},
      {train + "--eval-every 10 -o " + x, "--reference"},
      {train + "--preview-every 10 -o " + x, "--preview"},
      {train + "--reference " + (dir / "missing.exr").string() + " -o " + x, "missing.exr"},
      {train + "--reference " + not_exr + " -o " + x, "not.exr"},
      {train + "--reference " + wrong_shape + " -o " + x, "wide.exr"},
      {train + "--preview " + kBox + " -o " + x, "--preview"},
      {train + "--reference " + all_nan + " -o " + x, "holds no finite value"},
      {train + "--reference " + reference + " --eval-spp 65537 -o " + x, "--eval-spp"},
      {train + "--reference " + reference + " --preview " + (dir / "p.png").string() + " --preview-every -1 -o " + x,
       "--preview-every"},
      {"compare " + reference + " " + all_nan, "holds no finite value"},
  };
  for (const auto& [args, culprit] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(x)) << args << ": refused after the run directory was made";
  }
}

}  // namespace
}  // namespace clr::test
