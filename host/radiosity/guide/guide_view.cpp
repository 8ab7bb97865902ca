#include "radiosity/guide/guide_view.hpp"

#include <cmath>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "radiosity/guide/i_module.hpp"
#include "radiosity/guide/vmf_mixture.hpp"
#include "radiosity/surface_query.hpp"
#include "radiosity/trained_model.hpp"

namespace clr::radiosity {

GuideView view_guide(cl::Context& ctx, const geometry::Geometry& geometry, nn::Network& radiance, nn::Network& guide,
                     float px, float py, int width, int height, int res) {
  const scene::Scene& scene = geometry.scene();
  const auto ray = scene.camera.resized(width, height).ray(px, py);
  Pcg32 rng(0, 1);
  const PathEnd seen = trace_to_surface(geometry, {ray.origin, ray.tnear, ray.direction}, rng, 8);
  if (!seen.at_surface)
    throw InputError("pixel " + nlohmann::json(int(px)).dump() + "," + nlohmann::json(int(py)).dump() +
                     " sees no surface the model learns (the background, or a path lost among delta surfaces)");
  const geometry::SurfacePoint& x = seen.point;
  const scene::BsdfPoint bsdf = x.bsdf(scene);
  const std::size_t W = std::size_t(2 * res), H = std::size_t(res), n = W * H, R = nn::kRawInputs;

  // Every map pixel's direction, and where the ray from x along it needs the N-Module.
  std::vector<float> dirs(n * 3), rows(n * R), fcos(n * 3), emitted(n * 3), throughput(n * 3), solid_angle(n);
  std::vector<int> lookup(n, -1);
  parallel_for(n, 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const double theta = (double(i / W) + 0.5) * M_PI / double(H), phi = (double(i % W) + 0.5) * 2 * M_PI / double(W);
      solid_angle[i] = float(std::sin(theta) * (M_PI / double(H)) * (2 * M_PI / double(W)));
      const Vec3 w = x.frame.to_world(
          Vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))));
      std::copy_n(&w.x, 3, &dirs[3 * i]);
      const Rgb f = bsdf.eval(seen.wo, w);
      std::copy_n(&f.x, 3, &fcos[3 * i]);
      if (f == Rgb(0.0f)) continue;
      Pcg32 path_rng(i, 2);
      const PathEnd end_of_ray = trace_to_surface(geometry, {x.spawn_origin(w), 0.0f, w}, path_rng, 8);
      std::copy_n(&end_of_ray.emitted.x, 3, &emitted[3 * i]);
      std::copy_n(&end_of_ray.throughput.x, 3, &throughput[3 * i]);
      if (end_of_ray.at_surface) {
        write_raw_row(scene, end_of_ray.point, end_of_ray.wo, &rows[i * R]);
        lookup[i] = 1;
      }
    }
  });
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (lookup[i] >= 0) {
      std::copy_n(&rows[i * R], R, &rows[k * R]);
      lookup[i] = int(k++);
    }
  std::vector<float> li(std::max<std::size_t>(1, k) * 3, 0.0f);
  if (k) radiance_query(ctx, radiance)(std::span<const float>(rows.data(), k * R), li);

  // q at every map direction from the guide's lobes at (x, ω_o).
  std::vector<float> point_row(R);
  write_raw_row(scene, x, seen.wo, point_row.data());
  const glm::vec3 frame_n = frame_normal(x.frame.n, seen.wo);
  cl::Buffer<float> row_dev(ctx, std::span<const float>(point_row)), raw(ctx, kVmfRaw),
      normal_dev(ctx, std::span<const float>(&frame_n.x, 3));
  guide.infer(row_dev, 1, raw);
  VmfMixture vmf(ctx);
  vmf.decode(raw, normal_dev, 1);
  const std::vector<float> zero(n, 0.0f);
  cl::Buffer<float> dirs_dev(ctx, std::span<const float>(dirs)), bsdf_pdf(ctx, std::span<const float>(zero)),
      pdf(ctx, n), q_dev(ctx, n);
  vmf.mixture_pdf(dirs_dev, bsdf_pdf, n, 0.0f, pdf, q_dev);
  const std::vector<float> q = q_dev.read();

  std::vector<double> t(n, 0.0);
  double F = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double rgb[3];
    for (std::size_t c = 0; c < 3; ++c) {
      double l = emitted[3 * i + c];
      if (lookup[i] >= 0) l += double(throughput[3 * i + c]) * li[3 * std::size_t(lookup[i]) + c];
      rgb[c] = fcos[3 * i + c] * l;
    }
    t[i] = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    F += t[i] * solid_angle[i];
  }
  GuideView view;
  view.q = image::Image(int(W), int(H));
  view.target = image::Image(int(W), int(H));
  for (std::size_t i = 0; i < n; ++i) {
    const double p = F > 0 ? t[i] / F : 0.0;
    for (int c = 0; c < 3; ++c) {
      view.q.rgb[3 * i + std::size_t(c)] = q[i];
      view.target.rgb[3 * i + std::size_t(c)] = float(p);
    }
    if (p > 0) {
      view.kl += p * std::log(p / std::max(double(q[i]), 1e-30)) * solid_angle[i];
      view.q_mass_lit += q[i] * solid_angle[i];
      view.lit_fraction += solid_angle[i] / (4 * M_PI);
    }
  }
  return view;
}

}  // namespace clr::radiosity
