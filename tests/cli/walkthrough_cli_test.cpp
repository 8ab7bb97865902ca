// `render --path/--orbit` as a user runs it: frames into a folder, a rerun that renders only what is missing, Ctrl-C
// that keeps finished frames, a folder of other frames refused, the video (or the message without ffmpeg), and the
// break-even check.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <thread>

#include "common/subprocess.hpp"
#include "support/background_cli.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

class WalkthroughCli : public CliRunDir {
 protected:
  WalkthroughCli() : CliRunDir("walkthrough_cli") {}
  void SetUp() override {
    CliRunDir::SetUp();
    if (HasFatalFailure() || IsSkipped()) return;
    run = (dir / "run").string();
    ASSERT_EQ(run_cli("train " + kBox + " --steps 2 --config " + config + " -o " + run).exit_code, 0);
  }
  std::string render(const std::string& args) const { return "render " + kBox + " --model " + run + " " + args; }
  static std::size_t count(const fs::path& folder, const std::string& extension) {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(folder)) n += e.path().extension() == extension;
    return n;
  }
  std::string run;
};

TEST_F(WalkthroughCli, FramesIntoAFolderAndARerunRendersOnlyWhatIsMissing) {
  const fs::path frames = dir / "frames";
  const std::string args = "--orbit 6 --width 16 --height 16 --spp 1 --png -o " + frames.string();
  auto r = run_cli(render(args));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count(frames, ".exr"), 6u);
  EXPECT_EQ(count(frames, ".png"), 6u);
  EXPECT_THAT(r.out, HasSubstr("6 rendered now"));
  const auto written = fs::last_write_time(frames / "frame_00003.exr");
  fs::remove(frames / "frame_00004.exr");
  r = run_cli(render(args));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("1 rendered now"));
  EXPECT_THAT(r.out, HasSubstr("5 from an earlier run"));
  EXPECT_EQ(fs::last_write_time(frames / "frame_00003.exr"), written);

  // Other frames into the same folder are refused, naming what changed; nothing is written.
  for (const auto& [other, culprit] :
       std::vector<std::pair<std::string, std::string>>{{"--orbit 6 --width 16 --height 16 --spp 2", "--spp"},
                                                        {"--orbit 7 --width 16 --height 16 --spp 1", "--orbit"},
                                                        {"--orbit 6 --width 8 --height 16 --spp 1", "--width"}}) {
    r = run_cli(render(other + " -o " + frames.string()));
    EXPECT_EQ(r.exit_code, 2) << other << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << other;
    EXPECT_EQ(count(frames, ".exr"), 6u);
  }
  // Options that belong to one mode only.
  for (const std::string& bad :
       {render("--orbit 2 --png x.png -o " + (dir / "f2").string()), render("--video v.mp4 -o x.exr"),
        render("--path-tracer-check 2 -o x.exr"), render("--orbit 2 --camera 0,1,6,0,1,0,0,1,0,40 -o f3"),
        render("--orbit 2 --video v.avi -o " + (dir / "f4").string())}) {
    r = run_cli(bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << ": " << r.err;
  }
}

TEST_F(WalkthroughCli, InterruptKeepsFinishedFramesAndARerunCompletes) {
  const fs::path frames = dir / "frames";
  const std::string args = "--orbit 1500 --width 32 --height 32 --spp 2 -o " + frames.string();
  const pid_t pid = spawn_cli(words(render(args)));
  ASSERT_GE(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while ((!fs::exists(frames) || count(frames, ".exr") < 20) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  const std::size_t kept = count(frames, ".exr");
  if (kept == 1500) GTEST_SKIP() << "the whole path rendered before the interrupt arrived";
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_GE(kept, 20u);
  for (const auto& e : fs::directory_iterator(frames))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
  const auto r = run_cli(render(args));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr(std::to_string(kept) + " from an earlier run"));
  EXPECT_EQ(count(frames, ".exr"), 1500u);
}

TEST_F(WalkthroughCli, AVideoWhereFfmpegIsAndAClearLineWhereItIsNot) {
  const fs::path frames = dir / "frames", video = dir / "orbit.mp4";
  const std::string args = "--orbit 4 --width 16 --height 16 --spp 1 --video " + video.string() + " -o ";
  auto r = run_cli(render(args + (dir / "nowhere").string()), "PATH=/nonexistent");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("ffmpeg is not installed"));
  EXPECT_FALSE(fs::exists(dir / "nowhere")) << "refused before any frame";
  if (find_program("ffmpeg").empty()) GTEST_SKIP() << "ffmpeg is not installed (apt-get install ffmpeg)";
  r = run_cli(render(args + frames.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("video: " + video.string()));
  EXPECT_GT(fs::file_size(video), 0u);
  EXPECT_EQ(count(frames, ".png"), 4u) << "the video is made from the PNGs";
  // Folder and file names that mean something to ffmpeg are only names: '%' starts an image pattern, "a:b" reads as
  // a protocol.
  for (const std::string name : {"50%frames", "frames%05d", "file:frames", "%d"}) {
    const fs::path odd = dir / name, odd_video = dir / (name + ".gif");
    r = run_cli(render("--orbit 3 --width 16 --height 16 --spp 1 --video '" + odd_video.string() + "' -o '" +
                       odd.string() + "'"));
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_GT(fs::file_size(odd_video), 0u) << name;
    EXPECT_EQ(count(odd, ".png"), 3u) << name;
  }
}

// Waits up to `seconds` for `ready`; then SIGINT to `pid`, and how long it took to end (−1: it did not within 10 s,
// and was killed). `status` receives its wait status.
double interrupt_when(pid_t pid, const std::function<bool()>& ready, int& status, int seconds = 120) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (!ready() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(pid, SIGINT);
  const auto sent = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - sent < std::chrono::seconds(10)) {
    if (waitpid(pid, &status, WNOHANG) == pid)
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

// Ctrl-C while ffmpeg runs reaches ffmpeg, and one that ignores it is killed a second later: the command ends within
// moments, with the frames kept and no video. The ffmpeg here is a stand-in on PATH that ignores SIGINT and SIGTERM.
TEST_F(WalkthroughCli, AStopReachesFfmpegAndEndsTheCommandWithinMoments) {
  const fs::path bin = dir / "bin", frames = dir / "frames", video = dir / "orbit.mp4", started = dir / "ffmpeg.pid";
  fs::create_directories(bin);
  std::ofstream(bin / "ffmpeg") << "#!/bin/sh\ntrap '' INT TERM\necho $$ > " << started.string()
                                << "\nwhile :; do sleep 0.05; done\n";
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  const std::string path = std::getenv("PATH");
  setenv("PATH", (bin.string() + ":" + path).c_str(), 1);  // the child inherits it
  const pid_t pid = spawn_cli(
      words(render("--orbit 3 --width 8 --height 8 --spp 1 --video " + video.string() + " -o " + frames.string())));
  setenv("PATH", path.c_str(), 1);
  ASSERT_GE(pid, 0);
  int status = 0;
  const double took = interrupt_when(
      pid, [&] { return fs::exists(started) && fs::file_size(started) > 0; }, status);
  ASSERT_TRUE(fs::exists(started)) << "the stand-in ffmpeg never ran";
  ASSERT_GE(took, 0) << "still running 10 s after Ctrl-C";
  EXPECT_LT(took, 3.0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_EQ(count(frames, ".exr"), 3u) << "the frames are kept";
  EXPECT_FALSE(fs::exists(video));
  pid_t child = 0;
  std::ifstream(started) >> child;
  ASSERT_GT(child, 0);
  EXPECT_NE(::kill(child, 0), 0) << "the stand-in ffmpeg outlived the command";
}

// The break-even check's path tracing (here a reference of millions of samples a pixel) stops within moments too,
// keeping the frames and writing no figures.
TEST_F(WalkthroughCli, AStopEndsTheBreakEvenCheckWithinMoments) {
  const fs::path frames = dir / "frames";
  const pid_t pid =
      spawn_cli(words(render("--orbit 2 --width 32 --height 32 --spp 1 --path-tracer-check 1 "
                             "--check-spp 1048576 -o " +
                             frames.string())));
  ASSERT_GE(pid, 0);
  int status = 0;
  const double took = interrupt_when(
      pid, [&] { return fs::exists(frames) && count(frames, ".exr") == 2; }, status);
  ASSERT_GE(took, 0) << "still running 10 s after Ctrl-C";
  EXPECT_LT(took, 3.0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_EQ(count(frames, ".exr"), 2u);
  EXPECT_FALSE(fs::exists(frames / "break_even.json"));
}

TEST_F(WalkthroughCli, BreakEvenFiguresArePrintedAndWritten) {
  const fs::path frames = dir / "frames";
  const auto r = run_cli(
      render("--orbit 5 --width 8 --height 8 --spp 2 --path-tracer-check 2 --check-spp 16 -o " + frames.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("break-even: model"));
  const auto j = nlohmann::json::parse(std::ifstream(frames / "break_even.json"));
  EXPECT_GT(j.at("model_seconds_per_frame").get<double>(), 0);
  EXPECT_GT(j.at("path_tracer_seconds_per_frame").get<double>(), 0);
  EXPECT_GT(j.at("training_seconds").get<double>(), 0);
  ASSERT_EQ(j.at("checked_frames").size(), 2u);
  EXPECT_EQ(j.at("checked_frames")[0].at("frame"), 0);
  EXPECT_EQ(j.at("checked_frames")[1].at("frame"), 4) << "evenly spaced: the first and the last";
  for (const auto& f : j.at("checked_frames")) {
    EXPECT_GT(f.at("model_mape").get<double>(), 0);
    EXPECT_GT(f.at("path_tracer_spp").get<int>(), 0);
  }
}

// Records cannot be skipped: frames in a folder without its frames.json, or beyond the count its record holds, are
// refused rather than adopted under the settings given now; nothing is rendered.
TEST_F(WalkthroughCli, FramesWithoutTheirRecordAreRefused) {
  const fs::path frames = dir / "frames";
  const std::string args = "--orbit 3 --width 16 --height 16 --spp 1 -o " + frames.string();
  ASSERT_EQ(run_cli(render(args)).exit_code, 0);
  fs::remove(frames / "frames.json");
  auto r = run_cli(render(args));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("but no record of the settings"));
  EXPECT_FALSE(fs::exists(frames / "frames.json")) << "a record was made up for frames made without one";
  ASSERT_EQ(run_cli(render(args + "2")).exit_code, 0) << "a fresh folder";
  fs::copy_file(frames / "frame_00000.exr", fs::path(frames.string() + "2") / "frame_00007.exr");
  r = run_cli(render(args + "2"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("frame_00007.exr, beyond the 3 frames"));
}

// Refused before the work: a reference of the wrong size, and a break-even check that has no training time to
// weigh (a model file outside its run) or more frames to check than the path has. No image, no frame is written.
TEST_F(WalkthroughCli, UnusableReferenceAndBreakEvenInputsAreRefusedFirst) {
  const fs::path out = dir / "image.exr", frames = dir / "checked";
  ASSERT_EQ(run_cli("reference " + kBox + " --spp 1 --width 24 --height 16 -o " + (dir / "ref.exr").string()).exit_code,
            0);
  auto r = run_cli(render("--width 16 --height 16 --reference " + (dir / "ref.exr").string() + " -o " + out.string()));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--reference"));
  EXPECT_THAT(r.err, HasSubstr("reference is 24x16, image is 16x16"));
  EXPECT_FALSE(fs::exists(out)) << "the render was made before the reference was checked";
  const std::string model_file = "render " + kBox + " --model " + (fs::path(run) / "model.clr").string();
  for (const auto& [args, culprit] : std::vector<std::pair<std::string, std::string>>{
           {render("--orbit 3 --path-tracer-check 4"), "the path has only 3 frames"},
           {model_file + " --orbit 3 --path-tracer-check 1", "the check needs its run directory"}}) {
    r = run_cli(args + " --width 8 --height 8 --spp 1 -o " + frames.string());
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit)) << args;
    EXPECT_FALSE(fs::exists(frames / "frame_00000.exr")) << args << ": frames were rendered first";
  }
}

// SIGUSR1 and SIGQUIT are not swallowed by the compiler the OpenCL runtime loads (LLVM catches SIGUSR1 and does
// nothing): a render, which has no safe point to stop at, ends by the signal's default action.
TEST_F(WalkthroughCli, SignalsAreNotSwallowedByTheRuntime) {
  for (const int sig : {SIGUSR1, SIGQUIT}) {
    const pid_t pid = spawn_cli({"render", kBox, "--model", run, "--spp", "65536", "--width", "256", "--height", "256",
                                 "-o", (dir / "long.exr").string()});
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::seconds(4));  // the runtime loaded, kernels built, rendering
    ::kill(pid, sig);
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    pid_t done = 0;
    while ((done = waitpid(pid, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (done == 0) {
      ::kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      ADD_FAILURE() << "signal " << sig << " was swallowed: the render went on";
      continue;
    }
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "signal " << sig;
    EXPECT_FALSE(fs::exists(dir / "long.exr"));
  }
}

}  // namespace
}  // namespace clr::test
