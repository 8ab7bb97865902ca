#include "radiosity/training_batch.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <mutex>

#include "common/parallel.hpp"
#include "geometry/delta_lighting.hpp"
#include "radiosity/training_lights.hpp"

namespace clr::radiosity {
namespace {

// Distinct RNG streams for the uses of one (seed, step): surface points (0), ω_o (1), the uniforms of the guided
// directions (2), the incident half's per-point streams (3), and its light samples (4).
std::uint64_t stream_id(std::uint64_t seed, std::uint64_t step, std::uint64_t use) {
  return (seed * 0x9E3779B97F4A7C15ull) ^ (step * 0xBF58476D1CE4E5B9ull) ^ (use * 0x94D049BB133111EBull);
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

double thread_cpu_seconds() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Thread time of the incident loop's parts, kept per chunk and added once a chunk, only when the batch is timed.
// The chunk's total is its thread CPU time, read at its ends (a system call each), so that a thread the kernel took
// off its core for another process is not charged for the wait. Its split between the parts comes from wall-clock
// laps over one point in kLapEvery: laps at every sample would cost a tenth of the loop.
struct PartClock {
  static constexpr std::size_t kLapEvery = 8;
  bool on;
  double cpu_start = on ? thread_cpu_seconds() : 0.0;
  bool lapping = false;
  Clock::time_point last{};
  double bsdf = 0, tracing = 0, next_event = 0;  // the lapped points' wall seconds

  void start_point(std::size_t m) {
    lapping = on && m % kLapEvery == 0;
    if (lapping) last = Clock::now();
  }
  void lap(double& part) {
    if (!lapping) return;
    const auto now = Clock::now();
    part += std::chrono::duration<double>(now - last).count();
    last = now;
  }
  // Adds the chunk's thread time, split as its laps split; call once, at its end.
  void add_to(HostStageTimes& times) const {
    const double cpu = thread_cpu_seconds() - cpu_start, laps = bsdf + tracing + next_event;
    if (!(laps > 0)) return;
    times.bsdf_cpu += cpu * bsdf / laps;
    times.tracing_cpu += cpu * tracing / laps;
    times.next_event_cpu += cpu * next_event / laps;
  }
};

}  // namespace

void sample_training_points(const geometry::SurfaceSampler& sampler, const scene::Scene& scene,
                            const BatchSettings& settings, std::uint64_t seed, std::uint64_t step,
                            TrainingBatch& batch) {
  const auto start = Clock::now();
  const std::size_t M = settings.points, R = nn::kRawInputs;
  batch.points = M;
  batch.samples = settings.samples;
  batch.first_point = settings.first_point;
  batch.surface.resize(M);
  batch.wo.resize(M);
  batch.point_rows.resize(M * R);
  sampler.sample(stream_id(seed, step, 0), batch.surface, settings.first_point);
  parallel_for(M, 256, [&](std::size_t first, std::size_t last) {
    for (std::size_t m = first; m < last; ++m) {
      Pcg32 rng(settings.first_point + m, stream_id(seed, step, 1));
      const auto& x = batch.surface[m];
      // ω_o uniform over the directions the surface can scatter into (its black side is never queried): the whole
      // sphere for two-sided BSDFs, else mirrored into the scattering side's hemisphere.
      const scene::BsdfPoint bp = x.point.bsdf(scene);
      const Vec3 up = bp.untilted_normal != Vec3(0.0f) ? bp.untilted_normal : x.point.frame.n;
      Vec3 wo = scene::sample_uniform_sphere({rng.next_float(), rng.next_float()});
      if (!bp.seen_from_scattering_side(wo)) wo -= 2.0f * glm::dot(wo, up) * up;
      batch.wo[m] = wo;
      write_raw_row(scene, x.point, wo, &batch.point_rows[m * R]);
    }
  });
  if (batch.times) batch.times->points += seconds_since(start);
}

void trace_incident(const geometry::Geometry& geometry, const BatchSettings& settings, std::uint64_t seed,
                    std::uint64_t step, std::span<const float> guided, TrainingBatch& batch,
                    const geometry::LightSampler* lights) {
  const scene::Scene& scene = geometry.scene();
  const std::size_t M = batch.points, N = batch.samples, R = nn::kRawInputs;
  const float c = settings.bsdf_fraction;
  const bool guiding = c < 1.0f, keep = settings.guide;
  batch.weight.assign(M * N * 3, 0.0f);
  batch.emitted.assign(M * N * 3, 0.0f);
  batch.bsdf_pdf.assign(M * N, -1.0f);
  batch.lookup.assign(M * N, -1);
  batch.directions.assign(keep ? M * N * 3 : 0, 0.0f);
  const std::vector<scene::DeltaLight> deltas = training_delta_lights(scene);
  const bool delta_lights = !deltas.empty();
  // A first segment from a non-delta lobe escaping into the sun would count it twice: it is in the direct term.
  const bool sun = scene.environment && scene.environment->sun_as_directional();
  if (lights && lights->empty()) lights = nullptr;
  batch.direct.assign(delta_lights || lights ? M * 3 : 0, 0.0f);
  batch.light.assign(lights ? M * N * 3 : 0, 0.0f);
  std::vector<std::uint8_t> from_guide(M * N, 0);
  // Every sample's would-be lookup row, compacted afterwards in sample order (deterministic).
  std::vector<float> candidate(M * N * R);

  HostStageTimes* const times = batch.times;
  std::mutex times_mutex;
  auto start = Clock::now();
  parallel_for(M, 64, [&](std::size_t first, std::size_t last) {
    PartClock clock{times != nullptr};
    for (std::size_t m = first; m < last; ++m) {
      clock.start_point(m);
      Pcg32 rng(batch.first_point + m, stream_id(seed, step, 3));
      const auto& x = batch.surface[m];
      const Vec3& wo = batch.wo[m];
      const scene::BsdfPoint bsdf = x.point.bsdf(scene);
      Rgb direct(0.0f);
      if (delta_lights) direct = geometry::reflected_delta_lights(geometry, x.point, bsdf, wo, deltas);
      if (lights) {
        // One light sample beside each direction, from a stream of its own: the directions stay those drawn without.
        Pcg32 light_rng(batch.first_point + m, stream_id(seed, step, 4));
        Rgb sum(0.0f);
        for (std::size_t n = 0; n < N; ++n) {
          const Rgb l = geometry::next_event(geometry, *lights, x.point, bsdf, wo, light_rng);
          std::copy_n(&l.x, 3, &batch.light[3 * (m * N + n)]);
          sum += l;
        }
        direct += sum / float(N);
      }
      if (!batch.direct.empty()) std::copy_n(&direct.x, 3, &batch.direct[3 * m]);
      clock.lap(clock.next_event);
      for (std::size_t n = 0; n < N; ++n) {
        const std::size_t s = m * N + n;
        Vec3 wi;
        Rgb fcos(0.0f);
        bool delta = false;
        if (guiding && rng.next_float() >= c) {
          // A direction from q: the BSDF is evaluated there (its pdf joins p̃ on the device).
          from_guide[s] = 1;
          wi = Vec3(guided[3 * s], guided[3 * s + 1], guided[3 * s + 2]);
          fcos = bsdf.eval(wo, wi);
          batch.bsdf_pdf[s] = bsdf.pdf(wo, wi);
        } else {
          const float u_lobe = rng.next_float();
          const auto bs = bsdf.sample(wo, u_lobe, {rng.next_float(), rng.next_float()});
          if (!bs) continue;
          wi = bs->wi;
          delta = bs->delta;
          // Undo the division by the pdf for a continuous lobe: p̃ replaces it. A delta lobe keeps its weight.
          fcos = delta ? bs->weight : bs->weight * bs->pdf;
          batch.bsdf_pdf[s] = delta ? -1.0f : bs->pdf;
        }
        if (keep) std::copy_n(&wi.x, 3, &batch.directions[3 * s]);
        clock.lap(clock.bsdf);
        if (fcos == Rgb(0.0f)) continue;
        PathEnd path = trace_to_surface(geometry, {x.point.spawn_origin(wi), 0.0f, wi}, rng, settings.max_delta_bounces,
                                        delta || !sun);
        if (lights && !delta && !scene::is_black(path.first_emitted)) {
          // The emission a light sample could also have drawn: its MIS weight against the light sampler's density.
          // The BSDF's density stands for p̃ (which, guided, is formed on the device): any weights that sum to one
          // with the light sample's for every direction keep the sum unbiased.
          const float p_light = lights->pdf_hit(path.first_hit ? &*path.first_hit : nullptr, x.point.position, wi);
          path.emitted -= path.first_emitted * (1.0f - geometry::power_heuristic(batch.bsdf_pdf[s], p_light));
        }
        for (int ch = 0; ch < 3; ++ch) {
          batch.weight[3 * s + ch] = fcos[ch] * path.throughput[ch];
          batch.emitted[3 * s + ch] = fcos[ch] * path.emitted[ch];
        }
        if (path.at_surface) {
          write_raw_row(scene, path.point, path.wo, &candidate[s * R]);
          batch.lookup[s] = 0;  // marked; numbered below
        }
        clock.lap(clock.tracing);
      }
    }
    if (times) {
      std::lock_guard lock(times_mutex);
      clock.add_to(*times);
    }
  });
  if (times) {
    times->incident += seconds_since(start);
    start = Clock::now();
  }

  batch.guided = std::size_t(std::count(from_guide.begin(), from_guide.end(), std::uint8_t(1)));
  // Without a guide p̃ is the BSDF's own density (the discrete lobe probability is already in a delta weight).
  batch.pdf.clear();
  if (!keep)
    for (const float p : batch.bsdf_pdf) batch.pdf.push_back(p < 0.0f ? 1.0f : p);

  std::size_t rows = 0;
  for (std::size_t s = 0; s < M * N; ++s)
    if (batch.lookup[s] >= 0) batch.lookup[s] = int(rows++);
  batch.incident_rows.resize(rows * R);
  for (std::size_t s = 0; s < M * N; ++s)
    if (batch.lookup[s] >= 0) std::copy_n(&candidate[s * R], R, &batch.incident_rows[std::size_t(batch.lookup[s]) * R]);
  if (times) times->packing += seconds_since(start);
}

void guide_uniforms(std::size_t points, std::size_t samples, std::uint64_t seed, std::uint64_t step,
                    std::vector<float>& u, std::size_t first_point) {
  u.resize(points * samples * 3);
  parallel_for(points, 256, [&](std::size_t first, std::size_t last) {
    for (std::size_t m = first; m < last; ++m) {
      Pcg32 rng(first_point + m, stream_id(seed, step, 2));
      for (std::size_t i = 0; i < samples * 3; ++i) u[m * samples * 3 + i] = rng.next_float();
    }
  });
}

}  // namespace clr::radiosity
