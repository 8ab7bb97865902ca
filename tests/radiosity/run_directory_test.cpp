// RUN_DIR as one object: its files, its lock, and what a resumed run reads back from them.
#include "radiosity/run_directory.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "common/error.hpp"

namespace clr::radiosity {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class RunDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override { fs::remove_all(dir); }
  void TearDown() override { fs::remove_all(dir); }
  static std::string text(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  const fs::path dir = fs::temp_directory_path() / ("clr_run_directory" + std::to_string(::getpid()));
};

TEST_F(RunDirectoryTest, StartWritesTheSettingsAndTheLogHeader) {
  TrainConfig config;
  config.method = Method::Nr;
  RunDirectory run = RunDirectory::create(dir);
  run.start(config);
  EXPECT_EQ(RunDirectory::load_config(dir).method, Method::Nr);
  EXPECT_EQ(text(RunDirectory::log_path(dir)), "step,seconds,loss,lookups,non_finite,learning_rate,residual_power\n");
  run.append_log({.step = 25, .seconds = 1.5, .loss = 0.25, .lookups = 0.5, .non_finite = 3});
  EXPECT_THAT(text(RunDirectory::log_path(dir)), HasSubstr("\n25,1.500,0.25,0.500,3,0,0\n"));
}

TEST_F(RunDirectoryTest, IsnrRowsCarryTheGuideColumns) {
  RunDirectory run = RunDirectory::create(dir);
  run.start(TrainConfig{});
  run.append_log({.step = 1, .guide_loss = 0.5, .guided_share = 0.25});
  const std::string log = text(RunDirectory::log_path(dir));
  EXPECT_THAT(log, HasSubstr(",guide_loss,guided_share\n"));
  EXPECT_THAT(log, HasSubstr(",0.5,0.2500\n"));
}

TEST_F(RunDirectoryTest, OneWriterAtATime) {
  RunDirectory first = RunDirectory::create(dir);
  first.start(TrainConfig{});
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  try {
    RunDirectory::resume(dir);
    FAIL() << "a second writer was let in";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("in use by another training"));
  }
}

TEST_F(RunDirectoryTest, ResumeReadsTheTrainingTimeAndClearsKilledWritersTemporaries) {
  {
    RunDirectory run = RunDirectory::create(dir);
    run.start(TrainConfig{});
    run.append_log({.step = 25, .seconds = 12.5});
  }
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  std::ofstream(dir / "model.clr.tmp4242") << "partial";
  std::ofstream(dir / "model.clr.tmpx") << "not ours";
  const RunDirectory run = RunDirectory::resume(dir);
  EXPECT_DOUBLE_EQ(run.seconds_trained(), 12.5);
  EXPECT_FALSE(fs::exists(dir / "model.clr.tmp4242"));
  EXPECT_TRUE(fs::exists(dir / "model.clr.tmpx")) << "only write_atomically's names are removed";
}

TEST_F(RunDirectoryTest, ALogRowThatIsNotATimeNamesItsLine) {
  {
    RunDirectory run = RunDirectory::create(dir);
    run.start(TrainConfig{});
  }
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  for (const char* seconds : {"nan", "-1", "inf", "soon"}) {
    std::ofstream(RunDirectory::log_path(dir)) << "step,seconds\n25," << seconds << ",0.1\n";
    try {
      RunDirectory::resume(dir);
      ADD_FAILURE() << seconds << " was read as a training time";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("log.csv:2:")) << seconds;
    }
  }
}

TEST_F(RunDirectoryTest, ARunWithoutAMethodIsNr) {
  fs::create_directories(dir);
  std::ofstream(RunDirectory::config_path(dir)) << R"({"samples": 8})";
  const TrainConfig config = RunDirectory::load_config(dir);
  EXPECT_EQ(config.method, Method::Nr);
  EXPECT_EQ(config.samples, 8);
}

TEST_F(RunDirectoryTest, AMalformedConfigNamesTheFile) {
  fs::create_directories(dir);
  std::ofstream(RunDirectory::config_path(dir)) << R"({"method": "pt"})";
  try {
    RunDirectory::load_config(dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("config.json: method must be isnr or nr"));
  }
}

}  // namespace
}  // namespace clr::radiosity
