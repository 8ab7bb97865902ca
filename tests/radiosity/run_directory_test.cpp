// RUN_DIR as one object: its files, its lock, and what a resumed run reads back from them.
#include "radiosity/run_directory.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "common/digest.hpp"
#include "common/error.hpp"
#include "nn/checkpoint.hpp"
#include "scene/fingerprint.hpp"

namespace clr::radiosity {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class RunDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override { fs::remove_all(dir); }
  void TearDown() override {
    fs::remove_all(dir);
    fs::remove_all(scenes);
  }
  static std::string text(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // A scene of `files` (the XML first), written into `folder` with the given contents.
  static scene::SceneFingerprint scene_of(const fs::path& folder,
                                          const std::vector<std::pair<std::string, std::string>>& files) {
    scene::Scene s;
    for (const auto& [name, content] : files) {
      fs::create_directories((folder / name).parent_path());
      std::ofstream(folder / name) << content;
      s.files.push_back(folder / name);
      s.file_digests.push_back(Digest().add_file(folder / name).hex());
    }
    return scene::fingerprint(s);
  }
  const fs::path dir = fs::temp_directory_path() / ("clr_run_directory" + std::to_string(::getpid()));
  const fs::path scenes = dir.string() + "_scenes";
  scene::SceneFingerprint cbox() const {
    return scene_of(scenes / "cbox", {{"scene.xml", "<scene/>"}, {"meshes/a.obj", "v 0 0 0"}});
  }
};

TEST_F(RunDirectoryTest, StartWritesTheSettingsAndTheLogHeader) {
  TrainConfig config;
  config.method = Method::Nr;
  config.batch = 1000;
  config.samples = 3;
  RunDirectory run = RunDirectory::create(dir);
  run.start(config, cbox());
  EXPECT_EQ(RunDirectory::load_config(dir).method, Method::Nr);
  EXPECT_EQ(text(RunDirectory::log_path(dir)),
            "step,seconds,loss,lookups,non_finite,learning_rate,residual_power,mape,mse,relmse,samples,mean_ratio\n");
  run.append_log({.step = 25, .seconds = 1.5, .loss = 0.25, .lookups = 0.5, .non_finite = 3});
  EXPECT_THAT(text(RunDirectory::log_path(dir)), HasSubstr("\n25,1.500,0.25,0.500,3,0,0,,,,75000,\n"))
      << "no evaluation: its columns empty; the samples seen: 25 steps of 1000 points × 3 directions";
}

// train --reference: the metrics as the shortest decimals that read back to the same doubles (what `compare
// --json` prints), and the last row replaced when the run's last step gains its evaluation after it was logged.
TEST_F(RunDirectoryTest, EvaluatedRowsCarryTheMetricsExactly) {
  TrainConfig config;
  config.method = Method::Nr;
  RunDirectory run = RunDirectory::create(dir);
  run.start(config, cbox());
  run.append_log({.step = 5, .seconds = 1});
  const image::Metrics m{.mape = 0.1, .mse = 1.0 / 3.0, .relmse = 2.5e-7, .mean_ratio = 1.25};
  run.replace_last_log_row({.step = 5, .seconds = 1, .evaluation = m});
  EXPECT_EQ(text(RunDirectory::log_path(dir)),
            "step,seconds,loss,lookups,non_finite,learning_rate,residual_power,mape,mse,relmse,samples,mean_ratio\n"
            "5,1.000,0,0.000,0,0,0,0.1,0.3333333333333333,2.5e-07,,1.25\n")
      << "a config whose batch is unresolved (0) cannot say the samples";
}

// A log written before today's columns existed gains them when the run resumes, so that every row has the header's
// fields: empty evaluations, the samples each row's step had seen, and empty mean ratios (the three older shapes).
TEST_F(RunDirectoryTest, ResumeAddsTheMissingColumnsToAnOlderLog) {
  const std::string guide = "step,seconds,loss,lookups,non_finite,learning_rate,residual_power,guide_loss,guided_share";
  const std::pair<std::string, std::string> older[] = {
      {guide + "\n25,1.500,0.25,0.500,3,0.005,1,0.5,0.2500\n30,2.000,0.25,0.500,0,0.005,1,0.5,0.2500\n", ""},
      {guide + ",mape,mse,relmse\n25,1.500,0.25,0.500,3,0.005,1,0.5,0.2500,,,\n"
               "30,2.000,0.25,0.500,0,0.005,1,0.5,0.2500,0.1,0.2,0.3\n",
       "0.1,0.2,0.3"},
      {guide + ",mape,mse,relmse,samples\n25,1.500,0.25,0.500,3,0.005,1,0.5,0.2500,,,,12800\n"
               "30,2.000,0.25,0.500,0,0.005,1,0.5,0.2500,0.1,0.2,0.3,15360\n",
       "0.1,0.2,0.3"}};
  for (const auto& [log, evaluation] : older) {
    fs::remove_all(dir);
    TrainConfig config;
    config.batch = 64;
    config.samples = 8;
    {
      RunDirectory run = RunDirectory::create(dir);
      run.start(config, cbox());
    }
    std::ofstream(RunDirectory::log_path(dir)) << log;
    std::ofstream(RunDirectory::model_path(dir)) << "x";
    const RunDirectory run = RunDirectory::resume(dir, cbox());
    EXPECT_DOUBLE_EQ(run.seconds_trained(), 2.0);
    EXPECT_EQ(text(RunDirectory::log_path(dir)),
              guide +
                  ",mape,mse,relmse,samples,mean_ratio\n25,1.500,0.25,0.500,3,0.005,1,0.5,0.2500,,,,12800,\n"
                  "30,2.000,0.25,0.500,0,0.005,1,0.5,0.2500," +
                  (evaluation.empty() ? ",," : evaluation) + ",15360,\n");
  }
}

// A header of another shape (a file someone edited) is not rewritten.
TEST_F(RunDirectoryTest, ResumeLeavesALogOfAnotherShapeAlone) {
  {
    RunDirectory run = RunDirectory::create(dir);
    run.start(TrainConfig{}, cbox());
  }
  const std::string log = "step,seconds,custom\n5,1.000,x\n";
  std::ofstream(RunDirectory::log_path(dir)) << log;
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  RunDirectory::resume(dir, cbox());
  EXPECT_EQ(text(RunDirectory::log_path(dir)), log);
}

TEST_F(RunDirectoryTest, IsnrRowsCarryTheGuideColumns) {
  RunDirectory run = RunDirectory::create(dir);
  run.start(TrainConfig{}, cbox());
  run.append_log({.step = 1, .guide_loss = 0.5, .guided_share = 0.25});
  const std::string log = text(RunDirectory::log_path(dir));
  EXPECT_THAT(log, HasSubstr(",guide_loss,guided_share,mape,mse,relmse,samples,mean_ratio\n"));
  EXPECT_THAT(log, HasSubstr(",0.5,0.2500,,,,,\n"));
}

TEST_F(RunDirectoryTest, OneWriterAtATime) {
  RunDirectory first = RunDirectory::create(dir);
  first.start(TrainConfig{}, cbox());
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  try {
    RunDirectory::resume(dir, cbox());
    FAIL() << "a second writer was let in";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("in use by another training"));
  }
}

TEST_F(RunDirectoryTest, ResumeReadsTheTrainingTimeAndClearsKilledWritersTemporaries) {
  {
    RunDirectory run = RunDirectory::create(dir);
    run.start(TrainConfig{}, cbox());
    run.append_log({.step = 25, .seconds = 12.5});
  }
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  std::ofstream(dir / "model.clr.tmp4242") << "partial";
  std::ofstream(dir / "model.clr.tmpx") << "not ours";
  const RunDirectory run = RunDirectory::resume(dir, cbox());
  EXPECT_DOUBLE_EQ(run.seconds_trained(), 12.5);
  EXPECT_FALSE(fs::exists(dir / "model.clr.tmp4242"));
  EXPECT_TRUE(fs::exists(dir / "model.clr.tmpx")) << "only write_atomically's names are removed";
}

TEST_F(RunDirectoryTest, ALogRowThatIsNotATimeNamesItsLine) {
  {
    RunDirectory run = RunDirectory::create(dir);
    run.start(TrainConfig{}, cbox());
  }
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  for (const char* seconds : {"nan", "-1", "inf", "soon"}) {
    std::ofstream(RunDirectory::log_path(dir)) << "step,seconds\n25," << seconds << ",0.1\n";
    try {
      RunDirectory::resume(dir, cbox());
      ADD_FAILURE() << seconds << " was read as a training time";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("log.csv:2:")) << seconds;
    }
  }
}

TEST_F(RunDirectoryTest, ARunBelongsToTheSceneItWasTrainedOn) {
  RunDirectory::create(dir).start(TrainConfig{}, cbox());
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  // The same files in another folder are the same scene (a copied or moved scene folder keeps its runs).
  const auto copy = scene_of(scenes / "copy", {{"scene.xml", "<scene/>"}, {"meshes/a.obj", "v 0 0 0"}});
  EXPECT_NO_THROW(RunDirectory::require_scene(dir, copy));
  EXPECT_NO_THROW(RunDirectory::require_scene(RunDirectory::model_path(dir), copy));
  EXPECT_NO_THROW(RunDirectory::resume(dir, copy));
  const std::vector<std::pair<scene::SceneFingerprint, std::string>> others = {
      {scene_of(scenes / "x", {{"scene.xml", "<scene version='3'/>"}, {"meshes/a.obj", "v 0 0 0"}}),
       "the scene file differs"},
      {scene_of(scenes / "y", {{"scene.xml", "<scene/>"}, {"meshes/a.obj", "v 0 0 1"}}), "meshes/a.obj differs"},
      {scene_of(scenes / "z", {{"scene.xml", "<scene/>"}, {"meshes/a.obj", "v 0 0 0"}, {"b.png", "p"}}),
       "b.png is read now, not then"},
      {scene_of(scenes / "w", {{"scene.xml", "<scene/>"}}), "meshes/a.obj was read then, not now"}};
  for (const auto& [other, why] : others) {
    for (const fs::path& run : {dir, RunDirectory::model_path(dir)}) {
      try {
        RunDirectory::require_scene(run, other);
        ADD_FAILURE() << why << ": another scene was accepted";
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(why));
        EXPECT_THAT(e.what(), HasSubstr((scenes / "cbox" / "scene.xml").string())) << "names the run's scene";
        EXPECT_THAT(e.what(), HasSubstr(other.scene.string())) << "names the scene given";
      }
    }
    EXPECT_THROW(RunDirectory::resume(dir, other), InputError) << why;
  }
}

// A model without its scene record cannot be matched to a scene: refused, not adopted (and recorded) under the scene
// given now. So is a model file taken out of its run.
TEST_F(RunDirectoryTest, AModelWithoutASceneRecordIsRefused) {
  RunDirectory::create(dir).start(TrainConfig{}, cbox());
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  fs::remove(RunDirectory::scene_path(dir));
  const auto other = scene_of(scenes / "y", {{"scene.xml", "<scene/>"}, {"meshes/a.obj", "v 0 0 1"}});
  for (const auto& scene : {cbox(), other}) {
    try {
      RunDirectory::require_scene(dir, scene);
      ADD_FAILURE() << "a model without its scene record was adopted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("no scene record"));
      EXPECT_THAT(e.what(), HasSubstr("scene.json"));
    }
    EXPECT_THROW(RunDirectory::resume(dir, scene), InputError);
  }
  EXPECT_FALSE(fs::exists(RunDirectory::scene_path(dir))) << "no record is made up for it";
  const fs::path loose = dir.parent_path() / ("loose_" + dir.filename().string());
  fs::create_directories(loose);
  fs::copy_file(RunDirectory::model_path(dir), loose / "renamed.clr");
  EXPECT_THROW(RunDirectory::require_scene(loose / "renamed.clr", cbox()), InputError) << "a model file out of its run";
  fs::remove_all(loose);
}

// A checkpoint carries its scene's digest: copied into another run (whose record matches another scene) it is
// refused; copied out of its run, alone, it is still checked, and read where the scene is its own.
TEST_F(RunDirectoryTest, AModelCarriesItsScene) {
  const auto other = scene_of(scenes / "y", {{"scene.xml", "<scene/>"}, {"meshes/a.obj", "v 0 0 1"}});
  nn::Checkpoint c;
  c.config_json = "{}";
  c.rng_state = "1 scene " + cbox().digest;  // as RunDirectory writes it
  c.tensors.emplace_back("mlp.params", std::vector<float>(4, 0.5f));
  RunDirectory::create(dir).start(TrainConfig{}, other);
  nn::write_checkpoint(RunDirectory::model_path(dir).string(), c);
  try {
    RunDirectory::require_scene(dir, other);
    ADD_FAILURE() << "a model copied into another scene's run was adopted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("copied from another run"));
  }
  const fs::path loose = dir.parent_path() / ("loose_" + dir.filename().string());
  fs::create_directories(loose);
  fs::copy_file(RunDirectory::model_path(dir), loose / "model.clr");
  EXPECT_NO_THROW(RunDirectory::require_scene(loose / "model.clr", cbox())) << "its own scene";
  EXPECT_THROW(RunDirectory::require_scene(loose / "model.clr", other), InputError);
  fs::remove_all(loose);
}

// The whole record is compared: a record whose file list was edited, or whose digest belongs to other files, is
// refused, not matched by its top-level digest alone.
TEST_F(RunDirectoryTest, TheWholeSceneRecordIsCompared) {
  RunDirectory::create(dir).start(TrainConfig{}, cbox());
  std::ofstream(RunDirectory::model_path(dir)) << "x";
  nlohmann::json record;
  std::ifstream(RunDirectory::scene_path(dir)) >> record;
  ASSERT_GE(record["files"].size(), 1u);
  record["files"].push_back({{"name", "meshes/extra.obj"}, {"digest", "0123"}});
  std::ofstream(RunDirectory::scene_path(dir)) << record.dump();
  try {
    RunDirectory::require_scene(dir, cbox());
    ADD_FAILURE() << "an edited record was matched by its digest";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("does not match the files it lists"));
  }
  // Two fingerprints with one digest but other files are not the same scene.
  auto a = cbox(), b = cbox();
  ASSERT_FALSE(b.files.empty());
  b.files.back().digest = "ffff";
  EXPECT_FALSE(a == b);
}

TEST_F(RunDirectoryTest, AMalformedSceneRecordNamesTheFile) {
  fs::create_directories(dir);
  for (const char* record : {R"({"scene": "a", "digest": 3, "files": []})", R"({"scene": "a", "digest": "0"})",
                             R"({"scene": "a", "digest": "0", "files": {}})",
                             R"({"scene": "a", "digest": "0", "files": [], "extra": 1})", "[1, 2"}) {
    std::ofstream(RunDirectory::scene_path(dir)) << record;
    try {
      RunDirectory::require_scene(dir, cbox());
      ADD_FAILURE() << record << " was read as a scene record";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("scene.json")) << record;
    }
  }
}

TEST_F(RunDirectoryTest, ARunWithoutAMethodIsNr) {
  fs::create_directories(dir);
  std::ofstream(RunDirectory::config_path(dir)) << R"({"samples": 8})";
  const TrainConfig config = RunDirectory::load_config(dir);
  EXPECT_EQ(config.method, Method::Nr);
  EXPECT_EQ(config.samples, 8);
  EXPECT_EQ(config.average_steps, 0) << "a run written before the weight average rendered its parameters";
  EXPECT_EQ(TrainConfig{}.average_steps, 100) << "where a new run averages";
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
