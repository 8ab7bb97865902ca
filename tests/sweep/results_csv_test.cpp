// The sweep's files without a device: results.csv round trip and its errors, the path tracer's time to an error,
// and the tables' shape.
#include "sweep/results_csv.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>

#include "common/error.hpp"
#include "sweep/path_tracing.hpp"
#include "sweep/tables.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

sweep::Row model_row(const std::string& method, sweep::Point point, double minutes, std::uint64_t steps, double mape) {
  sweep::Row r;
  r.kind = sweep::RowKind::Model;
  r.method = method;
  r.samples = 4;
  r.seed = 1;
  r.point = point;
  r.budget_minutes = minutes;
  r.steps = steps;
  r.seconds = std::isnan(minutes) ? 10 : minutes * 60;
  r.peak_device_mib = 12.5;
  r.spp = 16;
  r.render_seconds = 0.25;
  r.mape = mape;
  r.mse = mape / 10;
  r.relmse = mape / 5;
  r.residual = mape / 100;
  r.residual_se = mape / 1000;
  r.image = "runs/x/render.png";
  r.error_map = "runs/x/error.png";
  r.incident_samples = steps * 4096 * 4;
  return r;
}

sweep::Row pt_row(sweep::Point point, double minutes, int spp, double seconds, double mape) {
  sweep::Row r;
  r.kind = sweep::RowKind::PathTracing;
  r.method = "pt";
  r.point = point;
  r.budget_minutes = minutes;
  r.spp = spp;
  r.seconds = r.render_seconds = seconds;
  r.mape = mape;
  return r;
}

TEST(SweepResults, RoundTripAndKeys) {
  const fs::path path = fs::temp_directory_path() / ("clr_sweep_results_" + std::to_string(::getpid()) + ".csv");
  EXPECT_TRUE(sweep::read_results(path).empty()) << "no file yet: no rows";
  const std::vector<sweep::Row> rows = {model_row("isnr-ikl", sweep::Point::Budget, 0.5, 300, 0.25),
                                        model_row("nr", sweep::Point::Steps, sweep::kNone, 300, 0.3),
                                        pt_row(sweep::Point::Budget, 0.5, 1000, 29.5, 0.125)};
  sweep::write_results(path, rows);
  const auto back = sweep::read_results(path);
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(back[i].key(), rows[i].key());
    EXPECT_EQ(back[i].steps, rows[i].steps);
    EXPECT_EQ(back[i].mape, rows[i].mape);
    EXPECT_EQ(back[i].image, rows[i].image);
    EXPECT_EQ(back[i].incident_samples, rows[i].incident_samples);
    EXPECT_EQ(std::isnan(back[i].residual), std::isnan(rows[i].residual));
  }
  // Rows differ in their keys exactly where a rerun must not mistake one for the other.
  EXPECT_NE(rows[0].key(), model_row("isnr-ikl", sweep::Point::Budget, 1.0, 300, 0.25).key());
  EXPECT_NE(rows[0].key(), model_row("isnr-kl", sweep::Point::Budget, 0.5, 300, 0.25).key());

  std::ofstream(path, std::ios::app) << "model,nr,4,1,budget,1,x,1,1,16,1,1,1,1,0,1,1,a,b,1\n";
  try {
    sweep::read_results(path);
    FAIL() << "read a malformed row";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string() + ":5"));
  }
  // Kinds and points are names from a fixed list, not free text.
  sweep::write_results(path, rows);
  std::ofstream(path, std::ios::app) << "model,nr,4,1,halfway,1,1,1,1,16,1,1,1,1,0,1,1,a,b,1\n";
  try {
    sweep::read_results(path);
    FAIL() << "read an unknown point";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string() + ":5: unknown point 'halfway'"));
  }
  std::ofstream(path) << "step,seconds\n";
  EXPECT_THROW(sweep::read_results(path), InputError);
  // A results.csv from before the incident_samples column: read, its rows' samples unknown (0); rewritten whole.
  std::ofstream(path) << "kind,method,samples,seed,point,budget_minutes,steps,seconds,peak_device_mib,spp,"
                         "render_seconds,mape,mse,relmse,non_finite,residual,residual_se,image,error_map\n"
                         "model,nr,4,1,budget,1,300,60,1,16,1,0.25,1,1,0,1,1,a,b\n";
  const auto older = sweep::read_results(path);
  ASSERT_EQ(older.size(), 1u);
  EXPECT_EQ(older[0].steps, 300u);
  EXPECT_EQ(older[0].incident_samples, 0u);
  std::ofstream(path, std::ios::app) << "model,nr,4,1,budget,2,300,60,1,16,1,0.25,1,1,0,1,1,a,b,1\n";
  EXPECT_THROW(sweep::read_results(path), InputError) << "a row of today's shape under the older header";
  fs::remove(path);
}

TEST(SweepResults, PathTracingTimeToAnError) {
  const std::vector<sweep::Row> rows = {pt_row(sweep::Point::Progress, sweep::kNone, 1, 1.0, 0.4),
                                        pt_row(sweep::Point::Budget, 0.1, 4, 4.0, 0.2)};
  // Between two measured points: log–log interpolation (0.4 → 0.2 over 1 → 4 s; 0.2828 is half way in log).
  auto t = sweep::path_tracing_time_to(rows, 0.4 / std::sqrt(2.0));
  EXPECT_NEAR(t.seconds, 2.0, 1e-9);
  EXPECT_FALSE(t.extrapolated);
  // Beyond the last point and before the first: MAPE ∝ time^-1/2 from the nearest point.
  t = sweep::path_tracing_time_to(rows, 0.1);
  EXPECT_NEAR(t.seconds, 16.0, 1e-9);
  EXPECT_TRUE(t.extrapolated);
  EXPECT_NEAR(sweep::path_tracing_time_to(rows, 0.8).seconds, 0.25, 1e-9);
  EXPECT_TRUE(std::isnan(sweep::path_tracing_time_to({}, 0.1).seconds));
}

TEST(SweepResults, TablesHaveThePapersThreeShapes) {
  const std::vector<sweep::Row> rows = {
      model_row("isnr-ikl", sweep::Point::Budget, 0.5, 300, 0.25), model_row("nr", sweep::Point::Budget, 0.5, 700, 0.3),
      model_row("nr", sweep::Point::Steps, sweep::kNone, 300, 0.35),
      pt_row(sweep::Point::Progress, sweep::kNone, 1, 0.01, 0.9), pt_row(sweep::Point::Budget, 0.5, 1000, 29.5, 0.125)};
  const std::string md = sweep::tables_markdown(rows, "Sweep of test");
  for (const char* part : {"## Table 1 — equal steps", "## Table 2 — equal time", "## Table 3 — residual",
                           "against path tracing at equal error", "| 0.5min | 1 | nr, same steps | 300 | 4.915 M |",
                           "| 4 | 0.5min | nr | 1 | 700 | 11.47 M |", "path tracing, 1000 spp",
                           "| 4 | 0.5min | 0.003 | isnr-ikl | 0.0025 | 0.0035 |"})
    EXPECT_THAT(md, HasSubstr(part));
}

}  // namespace
}  // namespace clr::test
