// The host's half of a training batch: the same whatever the worker pool's size (every stream is keyed by the
// point's index, never by a thread), and its stages timed only when asked.
#include "radiosity/training_batch.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "common/parallel.hpp"
#include "geometry/geometry.hpp"
#include "scene/scene.hpp"

namespace clr::test {
namespace {

radiosity::TrainingBatch host_batch(const geometry::Geometry& g, radiosity::HostStageTimes* times) {
  const geometry::SurfaceSampler sampler(g.scene());
  radiosity::BatchSettings settings;
  settings.points = 3000;  // not a multiple of any chunk
  settings.samples = 3;
  radiosity::TrainingBatch batch;
  batch.times = times;
  radiosity::sample_training_points(sampler, g.scene(), settings, 11, 5, batch);
  radiosity::trace_incident(g, settings, 11, 5, {}, batch);
  return batch;
}

struct ThreadCountGuard {
  ~ThreadCountGuard() { set_thread_count(0); }
};

TEST(TrainingBatch, IsTheSameWhateverTheThreadCount) {
  const auto s = scene::load_scene(std::filesystem::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml");
  const geometry::Geometry g(s);
  ThreadCountGuard guard;
  const auto all = host_batch(g, nullptr);
  set_thread_count(1);
  const auto one = host_batch(g, nullptr);
  EXPECT_EQ(one.point_rows, all.point_rows);
  EXPECT_EQ(one.incident_rows, all.incident_rows);
  EXPECT_EQ(one.weight, all.weight);
  EXPECT_EQ(one.emitted, all.emitted);
  EXPECT_EQ(one.pdf, all.pdf);
  EXPECT_EQ(one.lookup, all.lookup);
  EXPECT_GT(all.lookups(), 0u);
}

TEST(TrainingBatch, TimesItsStagesOnlyWhenAsked) {
  const auto s = scene::load_scene(std::filesystem::path(CLR_SOURCE_DIR) / "scenes" / "cornell-box.xml");
  const geometry::Geometry g(s);
  radiosity::HostStageTimes times;
  const auto timed = host_batch(g, &times);
  EXPECT_GT(times.points, 0.0);
  EXPECT_GT(times.incident, 0.0);
  EXPECT_GT(times.bsdf_cpu, 0.0);
  EXPECT_GT(times.tracing_cpu, 0.0);
  EXPECT_GT(times.packing, 0.0);
  EXPECT_EQ(times.guide_read, 0.0);  // nothing guided
  // The thread time of the loop's parts cannot exceed its wall time on all workers.
  EXPECT_LE(times.bsdf_cpu + times.tracing_cpu + times.next_event_cpu,
            times.incident * double(worker_count()) * 1.05 + 1e-4);
  // Timing changes nothing in the batch.
  EXPECT_EQ(timed.incident_rows, host_batch(g, nullptr).incident_rows);
}

}  // namespace
}  // namespace clr::test
