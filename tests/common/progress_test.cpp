// The progress line's ETA: a resumed run's earlier work is not part of this process's rate; its final line.
#include "common/progress.hpp"

#include <gtest/gtest.h>

namespace clr {
namespace {

TEST(Progress, EtaOfAFreshRunIsItsRateOverWhatIsLeft) {
  // 25 of 100 in 10 s: 75 left at 2.5 a second.
  EXPECT_DOUBLE_EQ(eta_seconds(10, 25, 0, 100), 30);
}

TEST(Progress, EtaOfAResumedRunTakesOnlyThisProcesssRate) {
  // A run resumed at 214 s of a 600-s budget, 25 s later at 239 s: 361 s of training left at one second a second
  // (counting the earlier 214 s as this process's work would give 38 s).
  EXPECT_DOUBLE_EQ(eta_seconds(25, 239, 214, 600), 361);
}

TEST(Progress, NoEtaBeforeAnyWorkOfThisProcess) {
  EXPECT_EQ(eta_seconds(3, 50, 50, 100), 0);
  EXPECT_EQ(eta_seconds(0, 0, 0, 100), 0);
}

// Threads report as they finish, in any order: the final line holds the most that was reported, not the last report
// (a render's final line read "reference  25.0%" when a thread's report of its earlier rows came in last).
TEST(Progress, TheFinalLineHoldsTheMostReportedWhateverTheOrder) {
  ::testing::internal::CaptureStderr();
  {
    Progress p("work", 8, 1000.0);
    p.update(8);
    p.update(2);
    p.finish();
  }
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("work 100.0%"), std::string::npos) << err;
  EXPECT_EQ(err.find("25.0%"), std::string::npos) << err;
}

}  // namespace
}  // namespace clr
