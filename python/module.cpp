// clradiosity._clradiosity: the Python module's native half (docs/python.md), a thin layer over the code the CLI
// calls — scene loading, radiosity::train, the renderers, the metrics. python/clradiosity/__init__.py gives it its
// Python shape (keyword arguments, numpy arrays, Run objects).
//
// Long calls release the GIL. SIGINT and SIGTERM stop them as they stop the CLI (a training checkpoints); the call
// then raises KeyboardInterrupt, or ends the process by SIGTERM after the checkpoint. Bad input raises ValueError with
// the CLI's one line, any other failure RuntimeError with the CLI's (out of memory: which setting to lower).
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <csignal>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cl/context.hpp"
#include "cl/device.hpp"
#include "cl/device_json.hpp"
#include "cli/failure_message.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/parallel.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "geometry/geometry.hpp"
#include "image/image.hpp"
#include "image/image_format.hpp"
#include "radiosity/renderer.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/trained_model.hpp"
#include "radiosity/trainer.hpp"
#include "radiosity/training_session.hpp"
#include "reference/path_tracer.hpp"
#include "report/folder_report.hpp"
#include "scene/fingerprint.hpp"

namespace py = pybind11;

namespace {

using namespace clr;

// An image for Python: numpy.asarray(image) is an (H, W, 3) float32 array over its pixels. The buffer protocol ties
// the module to no numpy version (pybind11's numpy bindings would tie it to one ABI).
struct PyImage {
  image::Image image;
};

image::Image from_buffer(const py::buffer& buffer, const char* what) {
  const py::buffer_info b = buffer.request();
  if (b.format != py::format_descriptor<float>::format() || b.ndim != 3 || b.shape[2] != 3)
    throw InputError(std::string(what) + ": give an (H, W, 3) float32 array");
  image::check_image_size(b.shape[1], b.shape[0], what);
  image::Image img(int(b.shape[1]), int(b.shape[0]));
  const auto* base = static_cast<const char*>(b.ptr);
  for (py::ssize_t y = 0; y < b.shape[0]; ++y)
    for (py::ssize_t x = 0; x < b.shape[1]; ++x)
      for (py::ssize_t c = 0; c < 3; ++c)
        img.pixel(int(x), int(y))[c] =
            *reinterpret_cast<const float*>(base + y * b.strides[0] + x * b.strides[1] + c * b.strides[2]);
  return img;
}

// A loaded scene: its files read once, its geometry built on first use and shared by later calls.
class Scene {
 public:
  // The path made absolute: what a run records of its scene must still name it after the program changes folder.
  Scene(const std::string& path, std::map<std::string, std::string> parameters, int sensor)
      : path_(path.empty() ? path : std::filesystem::absolute(path).lexically_normal().string()),
        parameters_(std::move(parameters)),
        sensor_(sensor),
        scene_(std::make_unique<scene::Scene>(scene::load_scene(path_, parameters_, sensor))) {}

  const std::string& path() const { return path_; }
  const std::map<std::string, std::string>& parameters() const { return parameters_; }
  int sensor() const { return sensor_; }
  const scene::Scene& scene() const { return *scene_; }
  const geometry::Geometry& geometry() {
    const std::lock_guard lock(mutex_);
    if (!geometry_) geometry_ = std::make_unique<geometry::Geometry>(*scene_);
    return *geometry_;
  }
  // The sensor's view, or another (camera: origin, target, up, vertical fov), for the renderers.
  scene::Camera view(const std::optional<std::vector<float>>& camera) const {
    if (camera) return scene_->camera.pinhole_view(*camera, "camera");
    scene::require_sensor(*scene_, path_);
    return scene_->camera;
  }

 private:
  std::string path_;
  std::map<std::string, std::string> parameters_;
  int sensor_;
  std::unique_ptr<scene::Scene> scene_;
  std::mutex mutex_;
  std::unique_ptr<geometry::Geometry> geometry_;
};

// Runs `work` without the GIL, stoppable by SIGINT/SIGTERM where the caller is Python's main thread (only it runs
// Python's signal handlers; elsewhere the process's handlers stay as they are). A stop ends the work at its next
// safe point; then Python's handler for the signal runs (SIGINT's default raises KeyboardInterrupt), or, where
// there is none, SIGINT raises KeyboardInterrupt and SIGTERM ends the process as Python's default would. A signal
// Python ignores does not stop the work. A stop a
// callback requested (request_stop) is forgotten after the call, on any thread.
template <class Work>
auto stoppable(Work&& work) {
  const py::module_ threading = py::module_::import("threading");
  const bool main_thread = threading.attr("current_thread")().is(threading.attr("main_thread")());
  std::optional<StopHandlerScope> handlers(std::in_place, main_thread);
  int signal = 0;
  auto result = [&] {
    py::gil_scoped_release released;
    auto r = work();
    signal = stop_signal();
    return r;
  }();
  const bool host_handled = signal != 0 && handlers->host_handles(signal);
  handlers.reset();
  // Python's own handler (its default raises KeyboardInterrupt; a program's may do anything) saw the signal too:
  // it runs now, and decides.
  if (host_handled) {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    return result;
  }
  if (signal == SIGTERM || signal == SIGHUP) std::raise(signal);
  if (signal != 0) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  return result;
}

// A trained model on a device, for rendering: the run's N-Module loaded once.
class Model {
 public:
  Model(const std::string& run, const std::string& device)
      : run_(run), ctx_(cl::select_device(device)), network_(radiosity::RunDirectory::load_radiance(ctx_, run)) {}

  std::uint64_t steps() const { return network_->steps(); }
  std::string device() const { return ctx_.device().describe(); }

  PyImage render(Scene& scene, const radiosity::RenderSettings& settings,
                 const std::optional<std::vector<float>>& camera) {
    radiosity::RunDirectory::require_scene(run_, scene::fingerprint(scene.scene()));
    const scene::Camera view = scene.view(camera);
    if (view.aperture_radius > 0)
      throw InputError(scene.path() +
                       ": a thinlens sensor is rendered by reference() only (give camera= for a "
                       "pinhole view of the model)");
    const auto& geometry = scene.geometry();
    return stoppable([&] {
      const std::lock_guard lock(mutex_);  // one render at a time on this model's device queue
      PyImage out;
      // Stopped between chunks (well under a second each), as the CLI's render is: Ctrl-C does not wait for the
      // whole image.
      radiosity::render_frames(
          geometry, std::span(&view, 1), radiosity::radiance_query(ctx_, *network_), settings,
          [&](std::size_t, image::Image&& img) { out.image = std::move(img); }, [] { return stop_requested(); });
      return out;
    });
  }

 private:
  std::string run_;
  cl::Context ctx_;
  std::unique_ptr<nn::Network> network_;
  std::mutex mutex_;
};

// A mode by its name, as the CLI's --mode; InputError naming `what` otherwise.
radiosity::RenderMode render_mode(const std::string& name, const char* what) {
  const auto& names = radiosity::render_mode_names();
  if (const auto it = names.find(name); it != names.end()) return it->second;
  throw InputError(std::string(what) + ": '" + name + "' is not lhs or rhs");
}

// What a training reports to its callback after every step.

// image::Metrics as `compare()` and `report()` return them: compare --json's keys.
py::dict metrics_dict(const image::Metrics& m) {
  py::dict d;
  d["mape"] = m.mape;
  d["mse"] = m.mse;
  d["relmse"] = m.relmse;
  d["mean_ratio"] = m.mean_ratio;
  d["non_finite"] = m.non_finite;
  d["reference_non_finite"] = m.reference_non_finite;
  return d;
}

py::dict step_report(const radiosity::Trainer& trainer, double seconds) {
  py::dict d;
  d["step"] = trainer.steps_done();
  d["loss"] = trainer.last_step().loss;
  d["seconds"] = seconds;
  return d;
}

}  // namespace

PYBIND11_MODULE(_clradiosity, m) {
  m.doc() = "clradiosity's native layer; use the clradiosity package";
  m.attr("__version__") = CLR_VERSION;

  // The CLI's exit-2 cases are ValueError, its exit-1 cases RuntimeError; both with its one line.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const py::error_already_set&) {
      throw;
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, cli::bounded_line(e.what()).c_str());
    } catch (const std::filesystem::filesystem_error& e) {
      PyErr_SetString(cli::path_at_fault(e) ? PyExc_ValueError : PyExc_RuntimeError,
                      cli::bounded_line(cli::path_at_fault(e) ? cli::path_message(e) : e.what()).c_str());
    } catch (const std::exception& e) {
      PyErr_SetString(PyExc_RuntimeError, cli::bounded_line(cli::failure_message(e, "")).c_str());
    }
  });

  py::class_<PyImage>(m, "Image", py::buffer_protocol())
      .def_buffer([](PyImage& i) {
        return py::buffer_info(i.image.rgb.data(), sizeof(float), py::format_descriptor<float>::format(), 3,
                               {py::ssize_t(i.image.height), py::ssize_t(i.image.width), py::ssize_t(3)},
                               {py::ssize_t(sizeof(float)) * 3 * i.image.width, py::ssize_t(sizeof(float)) * 3,
                                py::ssize_t(sizeof(float))});
      })
      .def_property_readonly("width", [](const PyImage& i) { return i.image.width; })
      .def_property_readonly("height", [](const PyImage& i) { return i.image.height; });

  m.def(
      "devices_json",
      [](const std::string& spec) {
        auto devices = cl::list_devices();
        const auto chosen = cl::select_device(devices, spec);
        if (!spec.empty()) devices = {chosen};
        auto out = nlohmann::json::array();
        for (const auto& d : devices) out.push_back(cl::to_json(d, d.device == chosen.device));
        return out.dump();
      },
      py::arg("spec") = "");

  m.def(
      "set_threads",
      [](int threads) {
        if (threads < 1 || threads > 4096)
          throw InputError("threads: " + std::to_string(threads) + " is not in [1, 4096]");
        set_thread_count(std::size_t(threads));
      },
      py::arg("threads"));
  m.def("set_quiet", [] { Progress::silence_process(); });

  py::class_<Scene>(m, "Scene")
      .def(py::init([](const std::string& path, const std::map<std::string, std::string>& parameters, int sensor) {
             py::gil_scoped_release released;
             return std::make_unique<Scene>(path, parameters, sensor);
           }),
           py::arg("path"), py::arg("parameters"), py::arg("sensor"))
      .def_property_readonly("path", &Scene::path)
      .def_property_readonly("parameters", &Scene::parameters)
      .def_property_readonly("sensor", &Scene::sensor)
      .def_property_readonly("sensor_count", [](const Scene& s) { return s.scene().sensor_count; })
      .def_property_readonly("digest", [](const Scene& s) { return scene::fingerprint(s.scene()).digest; })
      .def_property_readonly("files",
                             [](const Scene& s) {
                               std::vector<std::string> files;
                               for (const auto& f : s.scene().files) files.push_back(f.string());
                               return files;
                             })
      .def_property_readonly("has_sensor", [](const Scene& s) { return s.scene().has_sensor; })
      .def_property_readonly(
          "film", [](const Scene& s) { return py::make_tuple(s.scene().camera.width, s.scene().camera.height); })
      .def_property_readonly("sample_count", [](const Scene& s) { return s.scene().sample_count; })
      .def_property_readonly("shape_count", [](const Scene& s) { return s.scene().shapes.size(); });

  m.def("setting_flags", [] {
    std::vector<std::pair<std::string, std::string>> flags;
    for (const auto& f : radiosity::setting_flags()) flags.emplace_back(f.flag, f.pointer);
    return flags;
  });

  // train(request fields, settings patch as a callable, callback): radiosity::train, as `clradiosity train` runs it.
  m.def(
      "train",
      [](const Scene& scene, const std::string& run_dir, const std::string& device, const std::string& preset,
         const std::string& config_file, const std::string& config_json, bool resume,
         const std::function<void(py::dict)>& settings, const std::vector<std::string>& given,
         const std::string& reference, long eval_every, int eval_spp, const std::string& eval_mode,
         const std::string& preview, long preview_every, const std::function<bool(py::dict)>& callback) {
        radiosity::TrainRequest request;
        request.scene = scene.path();
        request.parameters = scene.parameters();
        request.sensor = scene.sensor();
        request.loaded = &scene.scene();
        request.run_dir = run_dir;
        request.device = device;
        request.preset = preset;
        request.config_file = config_file;
        if (!config_json.empty()) request.config = nlohmann::json::parse(config_json);
        request.resume = resume;
        request.evaluation.reference = reference;
        const auto flagged = [&given](const char* flag) {
          return std::find(given.begin(), given.end(), flag) != given.end();
        };
        // Given values go through as given: radiosity::train judges them, as it does the CLI's.
        if (flagged("--eval-every")) request.evaluation.every = eval_every;
        if (flagged("--eval-spp")) request.evaluation.spp = eval_spp;
        if (!eval_mode.empty()) request.evaluation.mode = render_mode(eval_mode, "eval_mode");
        request.preview = preview;
        request.preview_every = preview_every;
        request.given = flagged;
        // The settings patch is Python (keyword arguments over the config): applied with the GIL, as JSON.
        request.settings = [&settings](radiosity::TrainConfig& config) {
          if (!settings) return;
          py::gil_scoped_acquire held;
          const py::module_ json = py::module_::import("json");
          py::dict patch = json.attr("loads")(nlohmann::json(config).dump());
          settings(patch);
          config = radiosity::parse_train_config(nlohmann::json::parse(json.attr("dumps")(patch).cast<std::string>()));
        };
        std::optional<py::error_already_set> callback_failed;
        if (callback)
          request.after_step = [&](const radiosity::Trainer& trainer, double seconds) {
            py::gil_scoped_acquire held;
            try {
              // False ends the run at this step, with its checkpoint.
              if (!callback(step_report(trainer, seconds))) request_stop();
            } catch (py::error_already_set& e) {
              callback_failed = std::move(e);
              request_stop();
            }
          };
        const auto outcome = stoppable([&] { return radiosity::train(request); });
        if (callback_failed) throw std::move(*callback_failed);
        py::dict d;
        d["model"] = outcome.model.string();
        d["steps"] = outcome.steps;
        d["peak_device_mib"] = outcome.peak_device_mib;
        d["convergence"] = outcome.convergence ? py::object(py::str(outcome.convergence->string())) : py::none();
        d["side_output_failures"] = outcome.side_output_failures;
        return d;
      },
      py::arg("scene"), py::arg("run_dir"), py::arg("device"), py::arg("preset"), py::arg("config_file"),
      py::arg("config_json"), py::arg("resume"), py::arg("settings"), py::arg("given"), py::arg("reference"),
      py::arg("eval_every"), py::arg("eval_spp"), py::arg("eval_mode"), py::arg("preview"), py::arg("preview_every"),
      py::arg("callback"));

  py::class_<Model>(m, "Model")
      .def(py::init([](const std::string& run, const std::string& device) {
             py::gil_scoped_release released;
             return std::make_unique<Model>(run, device);
           }),
           py::arg("run"), py::arg("device"))
      .def_property_readonly("steps", &Model::steps)
      .def_property_readonly("device", &Model::device)
      .def(
          "render",
          [](Model& model, Scene& scene, int width, int height, int spp, std::uint64_t seed,
             const std::optional<std::vector<float>>& camera, const std::string& mode) {
            radiosity::RenderSettings settings;
            settings.width = width;
            settings.height = height;
            settings.spp = spp;
            settings.seed = seed;
            settings.mode = render_mode(mode, "mode");
            if (spp < 1 || spp > (1 << 16)) throw InputError("spp: " + std::to_string(spp) + " is not in [1, 65536]");
            return model.render(scene, settings, camera);
          },
          py::arg("scene"), py::arg("width"), py::arg("height"), py::arg("spp"), py::arg("seed"), py::arg("camera"),
          py::arg("mode"));

  m.def(
      "reference",
      [](Scene& scene, int spp, int width, int height, std::optional<int> max_depth, std::uint64_t seed,
         const std::optional<std::vector<float>>& camera) {
        reference::RenderOptions options;
        options.camera = scene.view(camera);
        options.spp = reference::samples_per_pixel(scene.scene(), scene.path(), spp, "spp");
        options.width = width;
        options.height = height;
        options.max_depth = max_depth;
        options.seed = seed;
        options.stoppable = true;
        scene::require_emitter(scene.scene(), scene.path());
        const auto& geometry = scene.geometry();
        return stoppable([&] { return PyImage{reference::render(geometry, options)}; });
      },
      py::arg("scene"), py::arg("spp"), py::arg("width"), py::arg("height"), py::arg("max_depth"), py::arg("seed"),
      py::arg("camera"));

  m.def(
      "compare",
      [](const py::buffer& image, const py::buffer& reference) {
        const auto img = from_buffer(image, "image");
        const auto ref = image::match_size(from_buffer(reference, "reference"), img);
        return metrics_dict(image::compare(img, ref));
      },
      py::arg("image"), py::arg("reference"));

  m.def(
      "report",
      [](const std::string& run, const std::string& out, const std::string& reference, const std::string& scene,
         int spp, bool path_tracer, double path_tracer_seconds, int path_tracer_max_spp, const std::string& device,
         int guide_grid, int guide_resolution) {
        report::require_report_path(out, "out");
        report::RunReportOptions options;
        options.run = run;
        options.reference = reference;
        options.scene = scene;
        options.spp = spp;
        options.path_tracer = path_tracer;
        options.path_tracer_seconds = path_tracer_seconds;
        options.path_tracer_max_spp = path_tracer_max_spp;
        options.device = device;
        options.guide_grid = guide_grid;
        options.guide_resolution = guide_resolution;
        report::ReportData data;
        std::size_t bytes = 0;
        {
          py::gil_scoped_release released;
          data = report::folder_report(options);
          const std::string page = report::report_html(data);
          write_text_atomically(out, page);
          bytes = page.size();
        }
        py::dict result, images;
        for (const auto& img : data.images) {
          py::dict e = img.metrics ? metrics_dict(*img.metrics) : py::dict();
          e["title"] = img.title;
          e["notes"] = img.notes;
          images[py::str(img.key)] = e;
        }
        result["path"] = out;
        result["bytes"] = bytes;
        result["images"] = images;
        return result;
      },
      py::arg("run"), py::arg("out"), py::arg("reference"), py::arg("scene"), py::arg("spp"), py::arg("path_tracer"),
      py::arg("path_tracer_seconds"), py::arg("path_tracer_max_spp"), py::arg("device"), py::arg("guide_grid"),
      py::arg("guide_resolution"));

  m.def(
      "read_image",
      [](const std::string& path) {
        py::gil_scoped_release released;
        return PyImage{image::read_exr(path)};
      },
      py::arg("path"));

  m.def(
      "write_image",
      [](const std::string& path, const py::buffer& pixels, const std::map<std::string, std::string>& attributes) {
        const auto format = image::output_format(path, "path");
        const auto img = from_buffer(pixels, "image");
        py::gil_scoped_release released;
        image::write_image(path, img, format, attributes);
      },
      py::arg("path"), py::arg("image"), py::arg("attributes"));
}
