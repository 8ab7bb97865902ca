// Faults a run meets (issue 16): SIGTERM, SIGKILL while training and while a checkpoint is being written, and
// outputs that cannot be written. Each must leave a checkpoint that loads, or no file at all, and one clear line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

#include "cl/device.hpp"
#include "nn/checkpoint.hpp"
#include "support/background_cli.hpp"
#include "support/cli_run_dir.hpp"
#include "support/run_cli.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kBox = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();

class FaultCli : public CliRunDir {
 protected:
  // checkpoint_every 1: a checkpoint is written after every step, so a kill at a random time often lands in the
  // middle of a write.
  FaultCli() : CliRunDir("fault_cli", {{"log_every", 1}, {"checkpoint_every", 1}}) {}

  // Starts `train` on the Cornell box in the background with its output discarded.
  pid_t start_training(const fs::path& run, bool resume) {
    if (resume) return spawn_cli({"train", kBox, "--resume", "--steps", "100000000", "-o", run.string()});
    return spawn_cli({"train", kBox, "--steps", "100000000", "--config", config, "-o", run.string()});
  }
};

TEST_F(FaultCli, TerminateWritesACheckpointAndExitsCleanly) {
  // SIGTERM (what `kill`, systemd and batch schedulers send) must behave as Ctrl-C does.
  const fs::path run = dir / "run";
  const pid_t pid = start_training(run, false);
  ASSERT_GE(pid, 0);
  ASSERT_TRUE(wait_for_lines(run / "log.csv", 3)) << "training did not start logging";
  ::kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143) << "a clean stop by SIGTERM exits 128 + 15";
  EXPECT_NO_THROW(nn::read_checkpoint((run / "model.clr").string()));
}

// A closed terminal (SIGHUP), Ctrl-\\ (SIGQUIT) and SIGUSR1 (which a runtime's handler swallowed) stop a training
// as cleanly as SIGTERM: a checkpoint, 128 + the signal, never a kill that loses the steps since the last one.
TEST_F(FaultCli, HangupAndQuitWriteACheckpointAndExitCleanly) {
  for (const int sig : {SIGHUP, SIGQUIT, SIGUSR1}) {
    const fs::path run = dir / ("run_" + std::to_string(sig));
    const pid_t pid = start_training(run, false);
    ASSERT_GE(pid, 0);
    ASSERT_TRUE(wait_for_lines(run / "log.csv", 3)) << "training did not start logging";
    ::kill(pid, sig);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "signal " << sig << " killed it (" << WTERMSIG(status) << ")";
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_NO_THROW(nn::read_checkpoint((run / "model.clr").string()));
  }
}

// What the process was started with ignored (`nohup` ignores SIGHUP, `trap '' INT` SIGINT) stays ignored: the
// training goes on through both, and SIGTERM, which was not ignored, still stops it cleanly.
TEST_F(FaultCli, IgnoredSignalsStayIgnored) {
  const fs::path run = dir / "ignored";
  struct sigaction ignore {
  }, hangup{}, interrupt{};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGHUP, &ignore, &hangup);  // inherited through fork and exec
  sigaction(SIGINT, &ignore, &interrupt);
  const pid_t pid = start_training(run, false);
  sigaction(SIGHUP, &hangup, nullptr);
  sigaction(SIGINT, &interrupt, nullptr);
  ASSERT_GE(pid, 0);
  ASSERT_TRUE(wait_for_lines(run / "log.csv", 3)) << "training did not start logging";
  ::kill(pid, SIGHUP);
  ::kill(pid, SIGINT);
  EXPECT_TRUE(wait_for_lines(run / "log.csv", lines_in(run / "log.csv") + 3)) << "an ignored signal stopped it";
  int status = 0;
  EXPECT_EQ(waitpid(pid, &status, WNOHANG), 0) << "it ended";
  ::kill(pid, SIGTERM);
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143);
  EXPECT_NO_THROW(nn::read_checkpoint((run / "model.clr").string()));
}

// A reader that closed its end of stdout's pipe ends the command with one line, not a silent death by SIGPIPE.
TEST(FaultCliPipe, AClosedStdoutEndsWithOneLine) {
  int out[2], err[2];
  ASSERT_EQ(::pipe(out), 0);
  ASSERT_EQ(::pipe(err), 0);
  ::close(out[0]);  // no reader, ever
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(out[1], 1);
    dup2(err[1], 2);
    ::close(err[0]);
    execl(CLR_CLI_PATH, "clradiosity", "--help", static_cast<char*>(nullptr));
    _exit(127);
  }
  ::close(out[1]);
  ::close(err[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = ::read(err[0], buffer, sizeof buffer)) > 0;) text.append(buffer, std::size_t(n));
  ::close(err[0]);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_THAT(text, HasSubstr("writing standard output"));
}

// The main job is a run like any other: a second one in the same folder is refused instead of deleting the
// first's run, and the first signal ends the whole job (no render, no 1024-spp reference) with 128 + the signal.
TEST_F(FaultCli, MainJobLocksItsFolderAndStopsAtTheFirstSignal) {
  const pid_t pid = spawn_cli({}, dir);
  ASSERT_GE(pid, 0);
  const fs::path out = dir / "clradiosity-out";
  ASSERT_TRUE(wait_for_lines(out / "cornell-box-run" / "log.csv", 2)) << "the main job did not start logging";
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  const auto second = run_cli("");
  fs::current_path(cwd);
  EXPECT_EQ(second.exit_code, 2) << second.err;
  EXPECT_THAT(second.err, HasSubstr("in use"));
  EXPECT_TRUE(fs::exists(out / "cornell-box-run" / "log.csv")) << "the second job deleted the first's run";
  ::kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143);
  EXPECT_FALSE(fs::exists(out / "cornell-box-reference-1024spp.exr")) << "went on to the reference after SIGTERM";
  EXPECT_FALSE(fs::exists(out / "cornell-box.exr"));
  EXPECT_NO_THROW(nn::read_checkpoint((out / "cornell-box-run" / "model.clr").string()));
}

// Time is training time: a process stopped (SIGSTOP, Ctrl-Z) and continued must not count the pause, or its time
// budget would be spent at once and the learning rate never annealed.
TEST_F(FaultCli, APauseIsNotTrainingTime) {
  const fs::path run = dir / "run";
  const pid_t pid = spawn_cli({"train", kBox, "--minutes", "0.05", "--config", config, "-o", run.string()});
  ASSERT_GE(pid, 0);
  ASSERT_TRUE(wait_for_lines(run / "log.csv", 3)) << "training did not start logging";
  ::kill(pid, SIGSTOP);
  std::this_thread::sleep_for(std::chrono::seconds(4));  // longer than the whole 3-second budget
  const std::size_t rows_at_pause = lines_in(run / "log.csv");
  ::kill(pid, SIGCONT);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_GT(lines_in(run / "log.csv"), rows_at_pause + 2) << "the run ended at the first step after the pause";
  std::ifstream in(run / "log.csv");
  std::string line, last;
  while (std::getline(in, line)) last = line;
  const double seconds = std::stod(last.substr(last.find(',') + 1));
  EXPECT_LT(seconds, 3.0 + 1.0) << "the 4-second pause was counted as training";
}

bool temporary_in(const fs::path& run) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(run, ec))
    if (entry.path().filename().string().rfind("model.clr.tmp", 0) == 0) return true;
  return false;
}

TEST_F(FaultCli, KillAtRandomTimesLeavesALoadableCheckpointAndResumes) {
  // SIGKILL cannot be caught: only the write order (temporary file, then rename) protects model.clr. A checkpoint
  // every step makes writes frequent. Odd rounds kill at a random moment; even rounds kill as soon as a checkpoint's
  // temporary appears, i.e. during a write. After each the file must load and the run resume from it.
  const fs::path run = dir / "run";
  std::mt19937 rng(16);
  std::uniform_int_distribution<int> delay_ms(0, 400);
  std::uint64_t last_step = 0;
  int mid_write = 0;  // kills that left a temporary behind: they certainly landed during a write
  for (int round = 0; round < 6; ++round) {
    const pid_t pid = start_training(run, round > 0);
    ASSERT_GE(pid, 0);
    // Let it log a row of this session first, and have written a first checkpoint: a kill during the very first
    // write leaves no model.clr at all, and nothing to resume (`--resume` then says so, exit 2).
    const std::size_t rows = lines_in(run / "log.csv");
    ASSERT_TRUE(wait_for_lines(run / "log.csv", rows + 2)) << "round " << round << ": no progress";
    const auto first = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!fs::exists(run / "model.clr") && std::chrono::steady_clock::now() < first)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (round % 2 == 0) {
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
      while (!temporary_in(run) && std::chrono::steady_clock::now() < deadline) {
      }
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    }
    ::kill(pid, SIGKILL);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status));
    mid_write += temporary_in(run);
    nn::Checkpoint c;
    ASSERT_NO_THROW(c = nn::read_checkpoint((run / "model.clr").string())) << "round " << round;
    EXPECT_GE(c.step, last_step) << "round " << round << ": the checkpoint went back in time";
    last_step = c.step;
  }
  std::printf("%d of 6 kills landed while a checkpoint was being written\n", mid_write);
  // The survivor renders, and a resume continues from it.
  auto r =
      run_cli("render " + kBox + " --model " + run.string() + " --width 8 --height 8 -o " + (dir / "out.exr").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("train " + kBox + " --resume --steps " + std::to_string(last_step + 2) + " -o " + run.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nn::read_checkpoint((run / "model.clr").string()).step, last_step + 2);
  EXPECT_FALSE(temporary_in(run)) << "a resume removes the temporaries that kills left";
}

// The lines of `err` that are the command's error (progress lines aside).
std::size_t error_lines(const std::string& err) {
  std::size_t n = 0;
  for (std::size_t at = err.find("clradiosity:"); at != std::string::npos; at = err.find("clradiosity:", at + 1)) ++n;
  return n;
}

TEST_F(FaultCli, UnwritableOutputsExitTwoBeforeTheWork) {
  // A path through a regular file cannot be created by anyone, root included (chmod does not stop root).
  const fs::path file = dir / "plain";
  std::ofstream(file) << "x";
  struct Case {
    std::string args, culprit;
  };
  std::vector<Case> cases = {
      {"train " + kBox + " --steps 1 --config " + config + " -o " + (file / "run").string(), (file / "run").string()},
      {"reference " + kBox + " --spp 1 --width 8 --height 8 -o " + (file / "x.exr").string(),
       (file / "x.exr").string()},
      {"reference " + kBox + " --spp 1 --width 8 --height 8 -o " + (file / "deeper" / "x.exr").string(),
       (file / "deeper" / "x.exr").string()},
  };
  // /proc takes no new files: its regular-looking files cannot be replaced through a temporary.
  if (fs::exists("/proc/version"))
    cases.push_back({"reference " + kBox + " --spp 1 --width 8 --height 8 -o /proc/version", "/proc/version"});
  if (::geteuid() != 0) {
    const fs::path locked = dir / "locked";
    fs::create_directories(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    cases.push_back({"train " + kBox + " --steps 1 -o " + (locked / "run").string(), (locked / "run").string()});
    cases.push_back({"reference " + kBox + " --spp 1 -o " + (locked / "x.exr").string(), (locked / "x.exr").string()});
  }
  for (const auto& c : cases) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(error_lines(r.err), 1u) << r.err;
    EXPECT_THAT(r.err, HasSubstr(c.culprit)) << c.args;
    // Checked before the work: a reference render of any size would print its progress first.
    EXPECT_THAT(r.err, Not(HasSubstr("100.0%"))) << c.args;
  }
  if (::geteuid() != 0) fs::permissions(dir / "locked", fs::perms::owner_all, fs::perm_options::replace);
}

// What watches a run fails without ending it: a preview whose folder is replaced by a file mid-run, a convergence
// figure whose path became a folder. Each is one warning line; the training runs to its budget, its checkpoint and
// log are whole, and it resumes.
TEST_F(FaultCli, SideOutputsThatFailCostNoTraining) {
  const fs::path run = dir / "run", previews = dir / "previews", reference = dir / "ref.exr";
  ASSERT_EQ(run_cli("reference " + kBox + " --spp 1 --width 16 --height 16 -o " + reference.string()).exit_code, 0);
  fs::create_directories(previews);
  std::thread saboteur([&] {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!fs::exists(previews / "p.png") && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    fs::remove_all(previews);
    std::ofstream(previews) << "a file where the preview's folder was";
    fs::create_directories(run / "convergence.svg" / "in the way");
  });
  const auto r = run_cli("train " + kBox + " --steps 150 --config " + config + " --preview " +
                         (previews / "p.png").string() + " --preview-every 5 --reference " + reference.string() +
                         " --eval-every 10 --eval-spp 1 -o " + run.string());
  saboteur.join();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto count = [&](const std::string& text) {
    std::size_t n = 0;
    for (auto at = r.err.find(text); at != std::string::npos; at = r.err.find(text, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("warning: --preview " + (previews / "p.png").string() + " failed"), 1u)
      << "one line for the preview however often it fails: " << r.err;
  EXPECT_EQ(count("warning: the convergence figure failed"), 1u) << r.err;
  EXPECT_THAT(r.err, HasSubstr("the model and its checkpoint are complete"));
  EXPECT_THAT(r.out, HasSubstr("(150 steps)"));
  EXPECT_THAT(r.out, Not(HasSubstr("preview: "))) << "the last preview was not written: not reported as written";
  std::ifstream log(run / "log.csv");
  std::string header, line, last;
  std::getline(log, header);
  while (std::getline(log, line))
    if (!line.empty()) last = line;
  EXPECT_EQ(last.substr(0, 4), "150,") << last;
  const auto cells = [](const std::string& row) {
    std::vector<std::string> out(1);
    for (const char c : row)
      if (c == ',')
        out.emplace_back();
      else
        out.back().push_back(c);
    return out;
  };
  const auto names = cells(header), values = cells(last);
  const auto mape = std::size_t(std::find(names.begin(), names.end(), "mape") - names.begin());
  ASSERT_LT(mape, values.size()) << header;
  EXPECT_FALSE(values[mape].empty()) << "the evaluations went on: the last row has its MAPE: " << last;
  fs::remove_all(run / "convergence.svg");
  const auto resumed = run_cli("train " + kBox + " --resume --steps 160 -o " + run.string());
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_THAT(resumed.out, HasSubstr("(160 steps)"));
}

// Under an address-space limit (ulimit -v) too tight for the paper's networks, training ends with the out-of-memory
// line (exit 1) at every limit, never in a runtime's assertion (PoCL asserts when a buffer it backs lazily cannot be
// mapped, exit 134), and leaves no partial output.
TEST_F(FaultCli, ATightAddressSpaceEndsWithTheOutOfMemoryLine) {
  for (int mib = 500; mib <= 1700; mib += 200) {
    const fs::path run = dir / ("limited" + std::to_string(mib));
    const std::string command = "ulimit -v " + std::to_string(mib * 1024) + " && '" + std::string(CLR_CLI_PATH) +
                                "' train " + kBox + " --preset paper --steps 1 -q -o " + run.string() + " 2>'" +
                                (dir / "limited.err").string() + "' >/dev/null";
    const int status = std::system(("bash -c \"" + command + "\"").c_str());
    ASSERT_TRUE(WIFEXITED(status));
    std::ifstream in(dir / "limited.err");
    const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const int code = WEXITSTATUS(status);
    EXPECT_TRUE(code == 0 || code == 1) << mib << " MiB: exit " << code << ": " << err;
    if (code == 1) {
      EXPECT_THAT(err, HasSubstr("out of host memory")) << mib << " MiB";
      EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
      // Nothing a restart would trip over: a run that never checkpointed leaves its folder as it found it.
      EXPECT_TRUE(!fs::exists(run) || fs::is_empty(run)) << mib << " MiB: files left in " << run;
    }
  }
}

TEST_F(FaultCli, AFullDeviceExitsOneAndNamesTheReason) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  // /dev/full fails every write with ENOSPC: the disk-full case, written through as a device is.
  const auto r = run_cli("reference " + kBox + " --spp 1 --width 8 --height 8 -o /dev/full");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(error_lines(r.err), 1u) << r.err;
  EXPECT_THAT(r.err, HasSubstr("/dev/full"));
  EXPECT_THAT(r.err, HasSubstr(std::strerror(ENOSPC)));
  // The whole image was made in a temporary first; it does not outlive the failure.
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
    EXPECT_EQ(entry.path().filename().string().find("-full.tmp"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace clr::test
