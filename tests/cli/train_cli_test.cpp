// train / render / residual as a user runs them: signals, bad input and the files a run leaves.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "cl/device.hpp"
#include "support/background_cli.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

class TrainCli : public CliRunDir {
 protected:
  TrainCli() : CliRunDir("train_cli") {}
};

TEST_F(TrainCli, InterruptWritesACheckpointAndExitsCleanly) {
  const fs::path run = dir / "run";
  const pid_t pid = spawn_cli({"train", kBox, "--steps", "100000000", "--config", config, "-o", run.string()});
  ASSERT_GE(pid, 0);
  // Wait until the run has logged a few rows, then interrupt it as Ctrl-C would.
  wait_for_lines(run / "log.csv", 3);
  ASSERT_GE(lines_in(run / "log.csv"), 3u) << "training did not start logging";
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 130) << "a clean stop by SIGINT exits 128 + 2";
  ASSERT_TRUE(fs::exists(run / "model.clr"));
  for (const auto& entry : fs::directory_iterator(run))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left behind: " << entry.path();

  // The checkpoint is usable: render from it and resume it.
  auto r = run_cli("render " + kBox + " --model " + run.string() + " --width 16 --height 16 -o " +
                   (dir / "out.exr").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out.exr"));
  r = run_cli("train " + kBox + " --resume --steps 1 -o " + run.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;  // already past 1 step: resumes, writes the checkpoint, stops

  // A resumed run keeps its settings: a flag asking for others is refused naming both; the same value is fine.
  const auto saved = nlohmann::json::parse(std::ifstream(run / "config.json"));
  for (const auto& [flags, fragment] : std::vector<std::pair<std::string, std::string>>{
           {"--method nr", "--method \"nr\" contradicts the run's \"isnr\""},
           {"--batch 999", "--batch 999 contradicts"},
           {"--learning-rate 0.01", "--learning-rate 0.01 contradicts"},
           {"--seed 7", "--seed 7 contradicts"}}) {
    r = run_cli("train " + kBox + " --resume --steps 1 " + flags + " -o " + run.string());
    EXPECT_EQ(r.exit_code, 2) << flags << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(fragment)) << flags;
  }
  r = run_cli("train " + kBox + " --resume --steps 1 --batch " + saved["batch"].dump() + " -o " + run.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(TrainCli, EachPresetRunsAndRecordsItsChoice) {
  std::map<std::string, nlohmann::json> saved;
  for (const std::string preset : {"preview", "balanced", "quality"}) {
    const fs::path run = dir / preset;
    // --batch beside the preset: flags override its choices (and keep the test fast).
    const auto r = run_cli("train " + kBox + " --preset " + preset + " --steps 2 --batch 64 -o " + run.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.err, HasSubstr("preset " + preset + ": batch"));
    EXPECT_THAT(r.err, HasSubstr("hash table 2^"));
    EXPECT_THAT(r.err, HasSubstr("batch 64 × 4")) << "the --batch flag overrides the preset's";
    std::ifstream in(run / "config.json");
    saved[preset] = nlohmann::json::parse(in);
    EXPECT_EQ(saved[preset]["preset"], preset);
    EXPECT_EQ(saved[preset]["batch"], 64);
    EXPECT_EQ(saved[preset]["steps"], 2);
  }
  const std::pair<std::string, std::string> cases[] = {
      {"train " + kBox + " --preset fast --steps 1 -o " + (dir / "x").string(), "--preset"},
      {"train " + kBox + " --preset preview --resume -o " + (dir / "preview").string(), "--resume"},
      {"--preset preview train " + kBox + " --steps 1 -o " + (dir / "x").string(), "--preset"},
  };
  for (const auto& [args, culprit] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << args;
  }
  EXPECT_FALSE(fs::exists(dir / "x"));
}

// An ISNR run as a user meets it: the I-Module's view of a pixel, the residual under guided sampling, and the
// errors of asking an NR run for its guide or giving impossible ISNR settings.
TEST_F(TrainCli, IsnrRunShowsItsGuide) {
  const std::string run = (dir / "isnr").string(), nr = (dir / "nr").string();
  auto r = run_cli("train " + kBox + " --steps 10 --config " + config + " -o " + run);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("isnr"));
  EXPECT_THAT(r.err, HasSubstr("I-Module"));
  r = run_cli("guide " + kBox + " --model " + run + " --pixel 64,64 --resolution 16 -o " + (dir / "g.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("KL(p||q)"));
  EXPECT_TRUE(fs::exists(dir / "g.png"));
  r = run_cli("residual " + kBox + " --model " + run + " --points 64 --samples 4 --sampling guide --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("\"sampling\":\"guide\""));

  ASSERT_EQ(run_cli("train " + kBox + " --steps 2 --method nr --config " + config + " -o " + nr).exit_code, 0);
  const std::pair<std::string, std::string> cases[] = {
      {"guide " + kBox + " --model " + nr + " --pixel 1,1 -o " + (dir / "n.png").string(), "without an I-Module"},
      {"guide " + kBox + " --model " + run + " --pixel 500,1 -o " + (dir / "n.png").string(), "outside"},
      {"residual " + kBox + " --model " + nr + " --sampling guide", "without an I-Module"},
      {"train " + kBox + " --steps 1 --bsdf-fraction 0 -o " + (dir / "x").string(), "--bsdf-fraction"},
      {"train " + kBox + " --steps 1 --is-loss nope -o " + (dir / "x").string(), "--is-loss"},
  };
  for (const auto& [args, culprit] : cases) {
    r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "n.png"));
}

// Every matrix-product backend the help and docs/cli.md name is accepted and recorded (fp32 was documented but
// refused by the option's check); anything else exits 2 naming the option.
TEST_F(TrainCli, EveryDocumentedGemmChoiceIsAccepted) {
  for (const std::string gemm : {"auto", "fp32", "own", "clblast"}) {
    const fs::path run = dir / ("gemm-" + gemm);
    const auto r = run_cli("train " + kBox + " --steps 1 --method nr --gemm " + gemm + " --config " + config + " -o " +
                           run.string());
    ASSERT_EQ(r.exit_code, 0) << gemm << "\n" << r.err;
    const auto saved = nlohmann::json::parse(std::ifstream(run / "config.json"));
    EXPECT_EQ(saved.at("network").at("gemm"), gemm);
  }
  const auto r = run_cli("train " + kBox + " --steps 1 --gemm tf16 -o " + (dir / "x").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("--gemm"));
}

// A run knows its scene: every command that reads it with another scene exits 2 naming both; a copy of the scene
// folder elsewhere is the same scene.
TEST_F(TrainCli, ARunRefusesAnotherScene) {
  const fs::path run = dir / "run";
  ASSERT_EQ(run_cli("train " + kBox + " --steps 2 --config " + config + " -o " + run.string()).exit_code, 0);
  std::ifstream in(kBox);
  std::string xml{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  fs::create_directories(dir / "copy");
  std::ofstream(dir / "copy" / "box.xml") << xml;
  const std::string copy = (dir / "copy" / "box.xml").string(), other = (dir / "other.xml").string();
  const std::string red = "0.63, 0.065, 0.05";
  ASSERT_NE(xml.find(red), std::string::npos);
  xml.replace(xml.find(red), red.size(), "0.6, 0.065, 0.05");
  std::ofstream(other) << xml;

  const std::string out = (dir / "out.exr").string();
  EXPECT_EQ(run_cli("render " + copy + " --model " + run.string() + " --width 8 --height 8 -o " + out).exit_code, 0);
  for (const std::string& args :
       {"render " + other + " --model " + run.string() + " --width 8 --height 8 -o " + out,
        "render " + other + " --model " + (run / "model.clr").string() + " --width 8 --height 8 -o " + out,
        "residual " + other + " --model " + run.string() + " --points 64 --samples 4",
        "guide " + other + " --model " + run.string() + " --pixel 4,4 --resolution 8 -o " + (dir / "g.png").string(),
        "train " + other + " --resume --steps 4 -o " + run.string(),
        "train " + other + " --steps 1 --config " + (run / "config.json").string() + " -o " + (dir / "x").string()}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr("is another scene")) << args;
    EXPECT_THAT(r.err, HasSubstr(kBox)) << args << ": names the run's scene";
    EXPECT_THAT(r.err, HasSubstr(other)) << args << ": names the scene given";
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "g.png"));
  // Reusing a run's settings for another scene is allowed when asked for; the scene's own box and inputs are used.
  const auto r = run_cli("train " + other + " --steps 1 --other-scene --config " + (run / "config.json").string() +
                         " -o " + (dir / "x").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(TrainCli, BadInputExitsTwoWithOneLine) {
  const std::string run = (dir / "run").string();
  fs::create_directories(dir / "empty");
  std::ofstream(dir / "empty" / "model.clr") << "not a checkpoint";
  const std::string out = " -o " + (dir / "x.exr").string();
  const std::pair<std::string, std::string> cases[] = {
      {"train " + kBox + " -o " + run, "--steps"},
      {"train " + (dir / "missing.xml").string() + " --steps 1 -o " + run, "missing.xml"},
      {"train " + kBox + " --steps 1 --samples 0 -o " + run, "samples"},
      {"train " + kBox + " --steps 1 --config " + (dir / "nope.json").string() + " -o " + run, "nope.json"},
      {"train " + kBox + " --steps 1 --resume -o " + run, "checkpoint"},
      {"train " + kBox + " --steps 1 --device nosuch -o " + run, "nosuch"},
      {"render " + kBox + " --model " + (dir / "none").string() + out, "none"},
      {"render " + kBox + " --model " + (dir / "empty").string() + out, "model.clr"},
      {"render " + kBox + " --model " + run + " --camera 0,0,0,0,0,0,0,1,0,40" + out, "--camera"},
      {"residual " + kBox + " --model " + (dir / "empty").string(), "model.clr"},
  };
  for (const auto& [args, culprit] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

// The modules' shapes are theirs: a config asking the N-Module for other than 3 outputs, or the I-Module for other
// than its mixture's, is refused by name before any training, and so is a run whose config.json was edited so.
TEST_F(TrainCli, NetworkShapesAreTheModulesOwn) {
  const auto with = [&](const std::string& name, const nlohmann::json& patch) {
    nlohmann::json small = nlohmann::json::parse(std::ifstream(config));
    small.merge_patch(patch);
    const fs::path file = dir / (name + ".json");
    std::ofstream(file) << small.dump();
    return file.string();
  };
  const std::pair<std::string, std::string> cases[] = {
      {"--method nr --config " + with("n16", {{"network", {{"outputs", 16}}}}), "network.outputs must be 3"},
      {"--method nr --config " + with("n1", {{"network", {{"outputs", 1}}}}), "network.outputs must be 3"},
      {"--method isnr --config " + with("g16", {{"guide", {{"outputs", 16}}}}), "guide.outputs must be 32"}};
  for (const auto& [args, why] : cases) {
    const auto r = run_cli("train " + kBox + " --steps 2 " + args + " -o " + (dir / "shape").string());
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(why)) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    fs::remove_all(dir / "shape");
  }
  const fs::path run = dir / "isnr";
  ASSERT_EQ(run_cli("train " + kBox + " --steps 2 --method isnr --config " + config + " -o " + run.string()).exit_code,
            0);
  nlohmann::json saved = nlohmann::json::parse(std::ifstream(run / "config.json"));
  saved["guide"]["outputs"] = 16;
  std::ofstream(run / "config.json") << saved.dump(2);
  for (const std::string& command :
       {"train " + kBox + " --resume --steps 4 -o " + run.string(),
        "guide " + kBox + " --model " + run.string() + " --pixel 5,5 --resolution 8 -o " + (dir / "g.png").string()}) {
    const auto r = run_cli(command);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr("guide.outputs must be 32")) << command;
  }
}

}  // namespace
}  // namespace clr::test
