#include "sweep/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "common/atomic_file.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/folder_record.hpp"
#include "common/run_lock.hpp"
#include "common/stop_signal.hpp"
#include "common/subprocess.hpp"
#include "reference/path_tracer.hpp"
#include "scene/fingerprint.hpp"
#include "scene/reference_record.hpp"
#include "sweep/configuration_run.hpp"
#include "sweep/path_tracing.hpp"
#include "sweep/tables.hpp"

namespace clr::sweep {
namespace fs = std::filesystem;
namespace {

void check_options(const SweepOptions& o) {
  if (o.minutes.empty()) throw InputError("--minutes: give at least one budget");
  for (double m : o.minutes)
    if (!(m > 0) || !std::isfinite(m)) throw InputError("--minutes: budgets must be finite and > 0");
  if (o.methods.empty()) throw InputError("--methods: give at least one method");
  for (const auto& m : o.methods) check_method(m);
  if (o.samples.empty()) throw InputError("--samples: give at least one sample count");
  if (!fs::is_regular_file(o.scene)) throw InputError("scene " + o.scene.string() + ": no such file");
  if (!o.reference.empty() && !fs::is_regular_file(o.reference))
    throw InputError("--reference " + o.reference.string() + ": no such file");
}

// The reference the metrics are taken against, at the render size: the given one (box-downsampled when it is an
// integer multiple of the size), or one the sweep path-traces — and says so — and keeps for its reruns.
image::Image reference_image(const geometry::Geometry& geometry, const SweepOptions& o, int width, int height) {
  const image::Image like(width, height);
  if (!o.reference.empty()) {
    std::map<std::string, std::string> attributes;
    image::Image given;
    try {
      given = image::match_size(image::read_exr(o.reference, &attributes), like);
      image::require_usable_reference(given, "--reference " + o.reference.string());
    } catch (const InputError& e) {
      throw InputError("--reference " + o.reference.string() + ": " + e.what());
    }
    if (const std::string warning = scene::check_reference_record(
            attributes, scene::fingerprint(geometry.scene()).digest, o.sensor, "--reference", o.reference.string());
        !warning.empty())
      std::fprintf(stderr, "sweep: warning: %s\n", warning.c_str());
    return given;
  }
  const fs::path path = o.dir / "reference.exr";
  if (fs::exists(path)) {
    std::printf("sweep: no --reference: using %s, path-traced by an earlier run of this sweep\n", path.c_str());
    return image::match_size(image::read_exr(path), like);
  }
  std::printf("sweep: no --reference: path-tracing one at %d spp into %s (--reference-spp)\n", o.reference_spp,
              path.c_str());
  std::fflush(stdout);
  reference::RenderOptions render;
  render.width = width;
  render.height = height;
  render.spp = o.reference_spp;
  render.max_depth = reference::kWholeTransport;
  render.progress = true;
  const auto img = reference::render(geometry, render);
  image::write_exr(path, img);
  return img;
}

// Runs bench/plot_sweep.py on SWEEP_DIR when a python3 has matplotlib; the CSV and tables never depend on it.
void draw_figures(const SweepOptions& o) {
  if (o.plot_script.empty()) return;
  // python3-matplotlib installs for Debian's interpreter, which a pyenv or conda python3 first on PATH hides.
  std::string python;
  for (const char* candidate : {"python3", "/usr/bin/python3"})
    if (run_program({candidate, "-c", "import matplotlib"}, true).ok) {
      python = candidate;
      break;
    }
  if (python.empty()) {
    std::printf("sweep: figures skipped: python3-matplotlib is missing (apt-get install python3-matplotlib)\n");
    return;
  }
  std::fflush(stdout);
  if (const ProgramResult r = run_program({python, o.plot_script.string(), o.dir.string()}, false); !r.ok)
    std::printf("sweep: figures failed: %s: %s (the tables are complete)\n", o.plot_script.c_str(), r.cause.c_str());
}

// What every row of SWEEP_DIR's table depends on. Budgets, methods, sample counts and seeds only add rows; a change
// of any of these would put rows measured another way into the same table.
nlohmann::json defining_options(const SweepOptions& o, const scene::Scene& scene, int width, int height) {
  nlohmann::json record = {
      {"scene", scene::fingerprint(scene).digest},
      {"reference", o.reference.empty() ? "path-traced at " + std::to_string(o.reference_spp) + " spp"
                                        : Digest().add_file(o.reference).hex()},
      {"width", width},
      {"height", height},
      {"render_spp", o.render_spp},
      {"residual_points", o.residual_points},
      {"residual_samples", o.residual_samples},
      {"config", o.base}};
  // Another sensor is another view; the first is left unrecorded, as sweeps recorded it before --sensor existed.
  if (o.sensor != 0) record["sensor"] = o.sensor;
  return record;
}

}  // namespace

void run_sweep(cl::Context& ctx, const SweepOptions& options) {
  check_options(options);
  SweepOptions o = options;
  std::sort(o.minutes.begin(), o.minutes.end());
  o.minutes.erase(std::unique(o.minutes.begin(), o.minutes.end()), o.minutes.end());
  const scene::Scene scene = scene::load_scene(o.scene, o.scene_parameters, o.sensor);
  scene::require_sensor(scene, o.scene);
  scene::require_emitter(scene, o.scene);
  const int width = o.width > 0 ? o.width : scene.camera.width, height = o.height > 0 ? o.height : scene.camera.height;
  image::check_image_size(width, height, "--width × --height");
  const fs::path results = o.dir / "results.csv";
  // The files SWEEP_DIR holds under fixed names must not be the sweep's inputs (a reference kept in SWEEP_DIR as
  // reference.png would not be, but as reference.exr it would be replaced when no --reference is given).
  std::vector<fs::path> inputs = scene.files;
  inputs.push_back(o.reference);
  require_outputs({{results, "results.csv in -o"},
                   {o.dir / "tables.md", "tables.md in -o"},
                   {o.dir / "sweep.json", "sweep.json in -o"},
                   {o.dir / "reference.png", "reference.png in -o"},
                   {o.reference.empty() ? o.dir / "reference.exr" : fs::path(), "reference.exr in -o"}},
                  inputs);
  // Read before any work: a damaged file is bad input, not a reason to train again.
  std::vector<Row> rows = read_results(results);
  const RunLock lock(o.dir);  // one sweep per SWEEP_DIR
  require_writable_directory(o.dir, "sweep directory");
  require_same_record(o.dir / "sweep.json", defining_options(o, scene, width, height), "a sweep",
                      {{"scene", "the scene (its files)"},
                       {"reference", "--reference (its content) or --reference-spp"},
                       {"width", "--width"},
                       {"height", "--height"},
                       {"sensor", "--sensor"},
                       {"render_spp", "--spp"},
                       {"residual_points", "--residual-points"},
                       {"residual_samples", "--residual-samples"},
                       {"config", "--config"}},
                      fs::exists(results) ? "rows (results.csv)" : "");
  install_stop_handlers();
  const geometry::Geometry geometry(scene);
  const image::Image reference = reference_image(geometry, o, width, height);
  image::write_png(o.dir / "reference.png", reference);

  const SweepContext sweep{ctx, geometry, reference, o, rows, results};
  for (const auto& config : plan_configurations(o.methods, o.samples, o.seeds)) {
    if (stop_requested()) break;
    run_configuration(sweep, config);
  }

  PathTracingPlan pt;
  pt.render.width = width;
  pt.render.height = height;
  pt.render.max_depth = reference::kWholeTransport;
  pt.budgets_minutes = o.minutes;
  pt.cap_seconds = o.path_tracing_cap * o.minutes.back() * 60.0;
  pt.target_mape = 0;
  for (const auto& r : rows)
    if (r.kind == RowKind::Model && r.point == Point::Budget && (pt.target_mape == 0 || r.mape < pt.target_mape))
      pt.target_mape = r.mape;
  if (!stop_requested())
    extend_path_tracing(geometry, reference, o.dir, pt, rows, [&] { write_results(results, rows); });

  write_text_atomically(o.dir / "tables.md", tables_markdown(rows, "Sweep of " + o.scene.string()));
  if (stop_requested()) {
    std::printf("sweep: stopped; %zu finished rows kept in %s — run the same command again to continue\n", rows.size(),
                results.c_str());
    return;
  }
  draw_figures(o);
  std::printf("sweep: %zu rows in %s, tables in %s\n", rows.size(), results.c_str(), (o.dir / "tables.md").c_str());
}

}  // namespace clr::sweep
