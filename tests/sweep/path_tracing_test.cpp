// The path tracer's progressive row on the bundled Cornell box at 16×16: doublings up to the first budget, points at
// the budgets, doubling towards a model's error until the cap, and a second call that continues the same render.
// About 4 s.
#include "sweep/path_tracing.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>

#include "common/stop_signal.hpp"
#include "scene/scene.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;

TEST(SweepPathTracing, BudgetsThenDoublingToTheCapAndAContinuation) {
  ASSERT_FALSE(stop_requested());
  const auto scene = scene::load_scene(fs::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml");
  const geometry::Geometry geometry(scene);
  reference::RenderOptions ref_options;
  ref_options.width = ref_options.height = 16;
  ref_options.spp = 256;
  const auto reference = reference::render(geometry, ref_options);
  const fs::path dir = fs::temp_directory_path() / ("clr_sweep_pt_" + std::to_string(::getpid()));
  fs::remove_all(dir);

  sweep::PathTracingPlan plan;
  plan.render.width = plan.render.height = 16;
  plan.budgets_minutes = {0.01, 0.005};  // 0.6 and 0.3 s
  plan.target_mape = 0;                  // no image reaches it: the cap ends the doubling
  plan.cap_seconds = 2.5;                // room for a doubling after a budget point at its bound below
  std::vector<sweep::Row> rows;
  int saves = 0;
  sweep::extend_path_tracing(geometry, reference, dir, plan, rows, [&] { ++saves; });
  ASSERT_GE(rows.size(), 4u);
  EXPECT_EQ(saves, int(rows.size()));
  EXPECT_EQ(rows[0].spp, 1) << "the timed short render";
  // Doublings fill the time before the first budget (one 16×16 sample takes well under a millisecond).
  ASSERT_EQ(rows[1].point, sweep::Point::Progress);
  EXPECT_EQ(rows[1].spp, 2);
  std::vector<sweep::Row> budgets;
  for (const auto& r : rows)
    if (r.point == sweep::Point::Budget) budgets.push_back(r);
  ASSERT_EQ(budgets.size(), 2u);
  EXPECT_EQ(budgets[0].budget_minutes, 0.005);
  EXPECT_EQ(budgets[1].budget_minutes, 0.01);
  // The budget's time is measured, and the passes bring it within 5 % of the budget or past it — by little on a
  // quiet machine; the bound leaves room for a shared one's stalls, and a budget the chain had already passed takes
  // the image as it was (the same spp twice).
  for (const auto& b : budgets) {
    EXPECT_GE(b.seconds, 0.95 * b.budget_minutes * 60);
    EXPECT_LT(b.seconds, 2 * b.budget_minutes * 60);
  }
  for (std::size_t i = 1; i < rows.size(); ++i) {
    EXPECT_GE(rows[i].spp, rows[i - 1].spp);
    EXPECT_GE(rows[i].seconds, rows[i - 1].seconds);
    if (rows[i].point == sweep::Point::Progress) {
      EXPECT_EQ(rows[i].spp, 2 * rows[i - 1].spp) << "doubling";
    }
    EXPECT_TRUE(fs::exists(dir / rows[i].image));
    EXPECT_TRUE(fs::exists(dir / rows[i].error_map));
  }
  EXPECT_EQ(rows.back().point, sweep::Point::Progress);
  EXPECT_LE(rows.back().seconds, plan.cap_seconds * 1.2) << "a pass expected to end past the cap was started";
  // Independent passes averaged: the error falls with the samples (1 spp against hundreds: several times lower).
  EXPECT_LT(rows.back().mape, 0.5 * rows.front().mape);

  // A larger cap continues the same render where it stopped; a target it has reached ends it at once.
  const auto before = rows.size();
  plan.cap_seconds = rows.back().seconds * 2.2;  // room for one doubling: its expected time is the time so far
  sweep::extend_path_tracing(geometry, reference, dir, plan, rows, [] {});
  ASSERT_GT(rows.size(), before);
  EXPECT_EQ(rows[before].spp, 2 * rows[before - 1].spp);
  const auto reached = rows.size();
  plan.target_mape = rows.back().mape;
  plan.cap_seconds *= 10;
  sweep::extend_path_tracing(geometry, reference, dir, plan, rows, [] {});
  EXPECT_EQ(rows.size(), reached);

  // Its time to an error it measured lies within the measured points.
  const auto t = sweep::path_tracing_time_to(rows, budgets[1].mape);
  EXPECT_FALSE(t.extrapolated);
  EXPECT_LE(t.seconds, budgets[1].seconds * 1.0001);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace clr::test
