// `clradiosity report`: a page made from a real (tiny) run, its images rendered by the engine where the run has
// none, and bad input refused with one line naming the culprit (exit 2) and no page left behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cl/device.hpp"
#include "image/image.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One tiny run for the whole suite: a 32×32 reference, 10 steps of NR with evaluations against it.
class ReportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (cl::list_devices().empty()) return;
    dir = fs::temp_directory_path() / ("clr_report_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "small.json") << R"({"batch": 256, "log_every": 5, "network": {"width": 32, "hidden_layers": 2,
              "encoder": {"grid": {"levels": 4, "log2_table": 12}}}})";
    reference = dir / "ref.exr";
    auto r = run_cli("reference " + kBox + " --spp 4 --width 32 --height 32 -o " + reference.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    run = dir / "run";
    r = run_cli("train " + kBox + " --method nr --steps 10 --config " + (dir / "small.json").string() +
                " --reference " + reference.string() + " --eval-every 5 --eval-spp 1 -o " + run.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(dir); }
  void SetUp() override {
    if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL device";
  }
  static fs::path dir, reference, run;
};
fs::path ReportCli::dir, ReportCli::reference, ReportCli::run;

TEST_F(ReportCli, RendersTheMissingImagesAndEmbedsThem) {
  const fs::path page = dir / "report.html";
  const auto r = run_cli("report " + run.string() + " --reference " + reference.string() +
                         " --spp 1 --path-tracer-max-spp 2 -o " + page.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("report: " + page.string()));
  const std::string html = read_text(page);
  // (find, not HasSubstr: a failure should name the key, not print a page of base64.)
  for (const char* key : {"\"key\":\"model\"", "\"key\":\"reference\"", "\"key\":\"path_tracer\"", "\"half_rgb\"",
                          "\"mape\"", "\"columns\":[\"step\"", "\"config\"", "\"scene digest\"", "\"spp cap\":\"2\"",
                          "\"budget seconds\"", "\"device\""})
    EXPECT_NE(html.find(key), std::string::npos) << key;
}

TEST_F(ReportCli, BadInputIsOneLineNamingTheCulpritAndLeavesNoPage) {
  const fs::path page = dir / "bad.html";
  const auto expect_refused = [&](const std::string& args, const std::string& culprit) {
    const auto r = run_cli("report " + args + " -o " + page.string());
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(page)) << args;
  };
  expect_refused((dir / "nosuchrun").string(), "nosuchrun: no such run folder");

  // A run whose log.csv was damaged.
  const fs::path broken = dir / "broken";
  fs::create_directories(broken);
  for (const char* f : {"config.json", "scene.json", "model.clr"}) fs::copy_file(run / f, broken / f);
  std::ofstream(broken / "log.csv") << read_text(run / "log.csv") << "12,oops\n";
  expect_refused(broken.string() + " --reference " + reference.string(), "log.csv:");

  // A reference of another size than the images given.
  image::Image small(16, 16);
  image::write_exr(dir / "small.exr", small);
  expect_refused(run.string() + " --reference " + reference.string() + " --model-image " + (dir / "small.exr").string(),
                 "--model-image " + (dir / "small.exr").string() + ": 16x16, but the reference is 32x32");
  // A reference whose shape is not the film's: the model would be rendered through another view.
  image::Image wide(32, 16);
  wide.rgb.assign(wide.rgb.size(), 0.5f);
  image::write_exr(dir / "wide.exr", wide);
  expect_refused(run.string() + " --reference " + (dir / "wide.exr").string(),
                 "32x16 is not the shape of the scene's film");
  // No reference given, and none recorded beside the scene.
  expect_refused(run.string(), "give --reference");
  // Not a page.
  const auto r = run_cli("report " + run.string() + " -o " + (dir / "x.png").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("must end in .html"));
}

// train --report writes the page at the end of the run, against its --reference.
TEST_F(ReportCli, TrainWritesTheReportAtTheEnd) {
  const fs::path page = dir / "trained.html";
  const auto r =
      run_cli("train " + kBox + " --method nr --steps 5 --config " + (dir / "small.json").string() + " --reference " +
              reference.string() + " -o " + (dir / "run2").string() + " --report " + page.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("report: " + page.string()));
  EXPECT_NE(read_text(page).find("\"key\":\"path_tracer\""), std::string::npos);
}

// A sweep folder is reported from its results.csv: every row, its images embedded, nothing rendered.
TEST_F(ReportCli, ASweepFolderIsReportedFromItsResults) {
  const fs::path sweep = dir / "sweep";
  auto r = run_cli("sweep " + kBox + " -o " + sweep.string() + " --reference " + reference.string() +
                   " --minutes 0.004 --methods nr --samples 4 --seeds 1 --width 32 --height 32 --config " +
                   (dir / "small.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path page = dir / "sweep.html";
  r = run_cli("report " + sweep.string() + " -o " + page.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_text(page);
  for (const char* key : {"\"sweep\":{\"rows\":[", "\"configuration\":\"nr N=4 seed 1\"",
                          "\"configuration\":\"path tracer\"", "data:image/png;base64,", "\"tables.md\""})
    EXPECT_NE(html.find(key), std::string::npos) << key;

  // A damaged results.csv is named, and no page is left.
  std::ofstream(sweep / "results.csv", std::ios::app) << "model,nr,x\n";
  const fs::path bad = dir / "sweep-bad.html";
  r = run_cli("report " + sweep.string() + " -o " + bad.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("results.csv"));
  EXPECT_FALSE(fs::exists(bad));
}

// A paper-tables folder (bench/paper_tables.sh's layout) is reported from its runs' logs and the path tracer's
// points, tables.md as its record.
TEST_F(ReportCli, APaperTablesFolderIsReportedFromItsRunsAndPoints) {
  const fs::path tables = dir / "paper";
  fs::create_directories(tables / "runs" / "box");
  fs::create_directories(tables / "path_tracer" / "box");
  fs::copy(run, tables / "runs" / "box" / "t1-nr");
  std::ofstream(tables / "runs" / "box" / "scene.json") << R"({"paper_scene": "", "width": 32, "height": 32})";
  std::ofstream(tables / "path_tracer" / "box" / "points.csv") << "spp,seconds,mape,mse,relmse\n1,0.01,0.7,0.3,0.5\n";
  std::ofstream(tables / "tables.md") << "# The paper's tables, regenerated\n";
  const fs::path page = dir / "paper.html";
  auto r = run_cli("report " + tables.string() + " -o " + page.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_text(page);
  for (const char* key : {"\"paper\":{\"scenes\":[", "\"label\":\"t1-nr\"", "\"path_tracer\":{\"mape\":[0.7]",
                          "# The paper's tables, regenerated"})
    EXPECT_NE(html.find(key), std::string::npos) << key;

  std::ofstream(tables / "path_tracer" / "box" / "points.csv", std::ios::app) << "2,x,0.5,0.2,0.4\n";
  r = run_cli("report " + tables.string() + " -o " + page.string() + ".bad.html");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("points.csv:3: seconds 'x' is not a number"));
}

}  // namespace
}  // namespace clr::test
