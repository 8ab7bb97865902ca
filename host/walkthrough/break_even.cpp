#include "walkthrough/break_even.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "common/stop_signal.hpp"
#include "image/image.hpp"
#include "reference/path_tracer.hpp"

namespace clr::walkthrough {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The path tracer's time to an image of MAPE `target` for one frame, progressively.
FrameCheck path_trace_to(const geometry::Geometry& geometry, const scene::Camera& camera, const image::Image& reference,
                         double target, const BreakEvenOptions& o) {
  FrameCheck check;
  reference::RenderOptions pass;
  pass.width = o.settings.width;
  pass.height = o.settings.height;
  pass.camera = camera;
  pass.max_depth = reference::kWholeTransport;
  pass.stoppable = true;
  image::Image sum(reference.width, reference.height);
  double seconds = 0, last_seconds = 0, last_mape = 0;
  int total_spp = 0;
  for (int spp = 1, index = 0;; spp *= 2, ++index) {
    pass.spp = spp;
    pass.seed = std::uint64_t(index) + 1;  // the reference's seed is far away (see below)
    const auto start = std::chrono::steady_clock::now();
    const image::Image img = reference::render(geometry, pass);
    const double t = seconds_since(start);
    if (stop_requested()) {  // the pass is incomplete: no figure from it
      check.path_tracer_seconds = NAN;
      return check;
    }
    seconds += t;
    total_spp += spp;
    image::Image mean(img.width, img.height);
    for (std::size_t i = 0; i < sum.rgb.size(); ++i) {
      sum.rgb[i] += img.rgb[i] * float(spp);
      mean.rgb[i] = sum.rgb[i] / float(total_spp);
    }
    const double mape = image::compare(mean, reference).mape;
    check.path_tracer_mape = mape;
    check.path_tracer_spp = total_spp;
    if (mape <= target) {
      // Between the previous point and this one, log–log: the time at which the chain crossed the target.
      check.path_tracer_seconds =
          index == 0 || !(last_mape > mape)
              ? seconds
              : std::exp(std::log(last_seconds) + (std::log(target) - std::log(last_mape)) *
                                                      (std::log(seconds) - std::log(last_seconds)) /
                                                      (std::log(mape) - std::log(last_mape)));
      return check;
    }
    last_seconds = seconds;
    last_mape = mape;
    // The next pass takes about as long as all before it.
    if (seconds + 2 * t > o.cap_seconds || stop_requested()) {
      check.path_tracer_seconds = seconds * (mape / target) * (mape / target);
      check.extrapolated = true;
      return check;
    }
  }
}

}  // namespace

nlohmann::json BreakEven::to_json() const {
  nlohmann::json frames_json = nlohmann::json::array();
  for (const auto& c : checks)
    frames_json.push_back({{"frame", c.frame},
                           {"model_mape", c.model_mape},
                           {"path_tracer_seconds", c.path_tracer_seconds},
                           {"path_tracer_spp", c.path_tracer_spp},
                           {"path_tracer_mape", c.path_tracer_mape},
                           {"extrapolated", c.extrapolated}});
  return {{"model_seconds_per_frame", model_seconds_per_frame},
          {"path_tracer_seconds_per_frame", path_tracer_seconds_per_frame},
          {"training_seconds", training_seconds},
          {"break_even_frames", std::isfinite(frames) ? nlohmann::json(frames) : nlohmann::json("never")},
          {"checked_frames", frames_json}};
}

BreakEven measure_break_even(const geometry::Geometry& geometry, const std::vector<scene::Camera>& cameras,
                             const radiosity::RadianceQuery& field, const BreakEvenOptions& o) {
  BreakEven result;
  result.training_seconds = o.training_seconds;
  const std::size_t n = cameras.size(), k = std::min<std::size_t>(std::size_t(std::max(1, o.frames_checked)), n);
  std::vector<std::size_t> frames;
  std::vector<scene::Camera> views;
  for (std::size_t i = 0; i < k; ++i) {
    frames.push_back(k == 1 ? 0 : (i * (n - 1) + (k - 1) / 2) / (k - 1));
    views.push_back(cameras[frames.back()]);
  }
  // The model's frames, back to back as a walkthrough renders them, timed after one untimed frame has built the
  // kernels for the chunks' sizes and warmed the device: one-off costs that no further frame pays.
  radiosity::render_frames(geometry, std::span(views.data(), 1), field, o.settings, [](std::size_t, image::Image&&) {});
  std::vector<image::Image> model(k);
  const auto start = std::chrono::steady_clock::now();
  radiosity::render_frames(geometry, views, field, o.settings,
                           [&](std::size_t i, image::Image&& img) { model[i] = std::move(img); });
  result.model_seconds_per_frame =
      o.model_seconds_per_frame > 0 ? o.model_seconds_per_frame : seconds_since(start) / double(k);

  for (std::size_t i = 0; i < k && !stop_requested(); ++i) {
    reference::RenderOptions ref;
    ref.width = o.settings.width;
    ref.height = o.settings.height;
    ref.camera = views[i];
    ref.spp = o.reference_spp;
    ref.max_depth = reference::kWholeTransport;
    ref.seed = (std::uint64_t(1) << 40) + frames[i];  // never a pass's seed
    ref.progress = true;
    ref.stoppable = true;
    const image::Image reference = reference::render(geometry, ref);
    if (stop_requested()) break;  // an incomplete reference measures nothing
    const double target = image::compare(model[i], reference).mape;
    // A model with non-finite pixels has no error the path tracer could match.
    FrameCheck check = std::isfinite(target) ? path_trace_to(geometry, views[i], reference, target, o) : FrameCheck{};
    if (!std::isfinite(target)) check.path_tracer_seconds = NAN;
    check.frame = frames[i];
    check.model_mape = target;
    result.checks.push_back(check);
    result.path_tracer_seconds_per_frame += check.path_tracer_seconds;
  }
  if (!result.checks.empty()) result.path_tracer_seconds_per_frame /= double(result.checks.size());
  const double saved = result.path_tracer_seconds_per_frame - result.model_seconds_per_frame;
  result.frames = saved > 0 ? result.training_seconds / saved : std::numeric_limits<double>::infinity();
  return result;
}

}  // namespace clr::walkthrough
