#include "sweep/path_tracing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/stop_signal.hpp"
#include "sweep/sweep_plan.hpp"

namespace clr::sweep {
namespace fs = std::filesystem;
namespace {

// Pass seeds start apart from 0, the seed of a reference the sweep path-traces itself: the reference and the
// chain's images must be independent, or the chain's MAPE would fall to 0 instead of to the reference's noise.
constexpr std::uint64_t kFirstPassSeed = 1000;

std::vector<const Row*> chain_points(const std::vector<Row>& rows) {
  std::vector<const Row*> points;
  for (const auto& r : rows)
    if (r.kind == RowKind::PathTracing) points.push_back(&r);
  std::sort(points.begin(), points.end(), [](const Row* a, const Row* b) { return a->spp < b->spp; });
  return points;
}

std::string image_name(int spp) { return "path_tracing/" + std::to_string(spp) + "spp"; }

}  // namespace

void extend_path_tracing(const geometry::Geometry& geometry, const image::Image& reference, const fs::path& sweep_dir,
                         const PathTracingPlan& plan, std::vector<Row>& rows, const std::function<void()>& save) {
  fs::create_directories(sweep_dir / "path_tracing");
  // The chain so far: its last point's image and totals.
  image::Image sum;  // spp-weighted: the mean image × spp
  int spp = 0;
  double seconds = 0;
  std::uint64_t passes = 0;
  if (const auto points = chain_points(rows); !points.empty()) {
    const Row& last = *points.back();
    sum = image::read_exr(sweep_dir / (image_name(last.spp) + ".exr"));
    for (float& v : sum.rgb) v *= float(last.spp);
    spp = last.spp;
    seconds = last.seconds;
    passes = points.size();
  }
  const auto add_point = [&](Point point, double budget_minutes) {
    image::Image mean = sum;
    for (float& v : mean.rgb) v /= float(spp);
    const auto m = image::compare(mean, reference);
    Row r;
    r.kind = RowKind::PathTracing;
    r.method = "pt";
    r.point = point;
    r.budget_minutes = budget_minutes;
    r.seconds = seconds;
    r.spp = spp;
    r.render_seconds = seconds;
    r.mape = m.mape;
    r.mse = m.mse;
    r.relmse = m.relmse;
    r.non_finite = m.non_finite;
    r.image = image_name(spp) + ".png";
    r.error_map = image_name(spp) + "_error.png";
    image::write_exr(sweep_dir / (image_name(spp) + ".exr"), mean);
    image::write_png(sweep_dir / r.image, mean);
    image::write_png(sweep_dir / r.error_map, image::error_map(mean, reference));
    rows.push_back(r);
    save();
    std::printf("path tracing: %d spp, %.2f s, MAPE %.4g%s\n", spp, seconds, m.mape,
                point == Point::Budget ? (", the " + budget_label(budget_minutes) + " budget").c_str() : "");
  };
  const auto pass = [&](int more) {
    reference::RenderOptions options = plan.render;
    options.spp = more;
    options.seed = kFirstPassSeed + passes++;
    reference::RenderStats stats;
    const auto img = reference::render(geometry, options, &stats);
    if (sum.rgb.empty()) sum = image::Image(img.width, img.height);
    for (std::size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += float(more) * img.rgb[i];
    spp += more;
    seconds += stats.seconds;
  };
  // Seconds per sample per pixel as measured so far; the first pass, one sample, is the timed short render.
  if (spp == 0) {
    if (stop_requested()) return;
    pass(1);
    add_point(Point::Progress, kNone);
  }
  const auto rate = [&] { return seconds / double(spp); };
  std::vector<double> budgets = plan.budgets_minutes;
  std::sort(budgets.begin(), budgets.end());
  // Doublings up to half the first budget: points between one sample and the first budget, where a model's error
  // at a short budget falls and where `path_tracing_time_to` would otherwise interpolate over four decades of time.
  // Their samples count towards the budget's image, so they cost only the passes' fixed overheads.
  while (!budgets.empty() && !stop_requested() && seconds + rate() * double(spp) <= 0.5 * budgets.front() * 60.0) {
    pass(spp);
    add_point(Point::Progress, kNone);
  }
  for (double minutes : budgets) {
    const bool done = std::any_of(rows.begin(), rows.end(), [&](const Row& r) {
      return r.kind == RowKind::PathTracing && r.point == Point::Budget && r.budget_minutes == minutes;
    });
    if (done) continue;
    // Passes until the render is within 5 % of the budget: the first rate, from one sample per pixel, includes the
    // render's fixed costs (threads, scheduling), so a pass sized by it alone falls short. A budget the chain has
    // already passed (the timing pass alone took longer) takes the image as it is, at its measured time.
    const double budget_s = minutes * 60.0;
    for (int refinement = 0; refinement < 8 && seconds < 0.95 * budget_s && !stop_requested(); ++refinement)
      pass(int(std::clamp(std::round((budget_s - seconds) / rate()), 1.0, double(1 << 24))));
    if (stop_requested()) return;
    add_point(Point::Budget, minutes);
  }
  // Doubling towards the best model's error, never starting a pass expected to end past the cap.
  while (!stop_requested() && chain_points(rows).back()->mape > plan.target_mape &&
         seconds + rate() * double(spp) <= plan.cap_seconds) {
    pass(spp);
    add_point(Point::Progress, kNone);
  }
}

TimeToError path_tracing_time_to(const std::vector<Row>& rows, double mape) {
  const auto points = chain_points(rows);
  if (points.empty() || !(mape > 0)) return {};
  const auto monte_carlo = [&](const Row& p) { return TimeToError{p.seconds * std::pow(p.mape / mape, 2.0), true}; };
  if (points.front()->mape <= mape) return monte_carlo(*points.front());
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i]->mape <= mape) {
      const Row &a = *points[i - 1], &b = *points[i];
      const double t = std::log(a.mape / mape) / std::log(a.mape / b.mape);
      return {std::exp(std::log(a.seconds) + t * std::log(b.seconds / a.seconds)), false};
    }
  return monte_carlo(*points.back());
}

}  // namespace clr::sweep
