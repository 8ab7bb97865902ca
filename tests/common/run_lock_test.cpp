// One training per run directory: a second writer is refused with exit 2, the lock dies with its holder.
#include "common/run_lock.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "cl/device.hpp"
#include "common/error.hpp"
#include "support/run_cli.hpp"

namespace clr {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class RunLockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("clr_run_lock_" + std::to_string(::getpid()));
    fs::remove_all(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  fs::path dir;
};

TEST_F(RunLockTest, SecondHolderIsRefusedUntilTheFirstLetsGo) {
  {
    const RunLock first(dir / "run");
    EXPECT_TRUE(fs::is_directory(dir / "run"));
    EXPECT_TRUE(fs::is_empty(dir / "run")) << "a fresh run needs its directory empty";
    try {
      const RunLock second(dir / "run");
      FAIL() << "two holders of one run directory";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr((dir / "run").string()));
      EXPECT_THAT(e.what(), HasSubstr("in use"));
    }
  }
  EXPECT_NO_THROW(RunLock again(dir / "run"));
}

TEST_F(RunLockTest, ResumingAMissingRunLeavesNoDirectory) {
  EXPECT_THROW(RunLock(dir / "missing", false), InputError);
  EXPECT_FALSE(fs::exists(dir / "missing"));
}

TEST_F(RunLockTest, LockOfAKilledProcessIsReleased) {
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const RunLock held(dir / "run");
    char c = 1;
    (void)!::write(ready[1], &c, 1);
    ::pause();  // until killed
    ::_exit(0);
  }
  char c;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_THROW(RunLock(dir / "run"), InputError);
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  EXPECT_NO_THROW(RunLock(dir / "run"));
  ::close(ready[0]);
  ::close(ready[1]);
}

TEST_F(RunLockTest, TrainOnALockedRunDirectoryExitsTwo) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL device";
  const RunLock held(dir / "run");  // stands for a training in progress
  const std::string box = (fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml").string();
  const auto r = test::run_cli("train " + box + " --steps 1 -o " + (dir / "run").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("in use by another training"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(fs::is_empty(dir / "run")) << "the refused run wrote into the directory";
}

}  // namespace
}  // namespace clr
