// A tool the CLI calls on (ffmpeg, python3 for the sweep's figures) that fails is one line: the last line it wrote
// on stderr (a traceback's error), or how it ended — never its whole output on the user's terminal.
#include "common/subprocess.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace clr::test {
namespace {

TEST(Subprocess, AFailureIsTheLastLineOnStderr) {
  const auto r = run_program({"sh", "-c",
                              "echo 'Traceback (most recent call last):' >&2; echo '  File \"plot.py\", line 3' >&2;"
                              "echo 'ValueError: no rows' >&2; echo >&2; exit 3"},
                             true);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.cause, "ValueError: no rows");
}

TEST(Subprocess, ASilentFailureSaysHowItEnded) {
  EXPECT_EQ(run_program({"sh", "-c", "exit 3"}, true).cause, "exit status 3");
  EXPECT_EQ(run_program({"sh", "-c", "kill -9 $$"}, true).cause, "killed by signal 9");
  const auto missing = run_program({"clradiosity-no-such-tool"}, true);
  EXPECT_FALSE(missing.ok);
  EXPECT_FALSE(missing.cause.empty());
}

TEST(Subprocess, SuccessHasNoCause) {
  const auto r = run_program({"sh", "-c", "echo warnings only >&2"}, true);
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.cause, "");
}

}  // namespace
}  // namespace clr::test
