#include "radiosity/run_directory.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "nn/checkpoint.hpp"
#include "radiosity/guide/i_module.hpp"
#include "radiosity/trained_model.hpp"

namespace clr::radiosity {
namespace fs = std::filesystem;
namespace {

constexpr const char* kLogHeader = "step,seconds,loss,lookups,non_finite,learning_rate,residual_power";
constexpr const char* kGuideLogColumns = ",guide_loss,guided_share";  // isnr runs only
// Later columns go last, so that the columns before keep their places for readers of older logs: the model's error
// against a reference (train --reference; empty in rows without an evaluation), then the incident samples seen, then
// the evaluated image's mean over the reference's (a runaway's first sign).
constexpr const char* kEvaluationLogColumns = ",mape,mse,relmse";
constexpr const char* kSamplesLogColumn = ",samples";
constexpr const char* kMeanRatioLogColumn = ",mean_ratio";

// The header's shapes, oldest first: each log written since has one of them; the last is today's.
enum class LogShape { Base, Evaluation, Samples, MeanRatio };
constexpr LogShape kLogShapes[] = {LogShape::Base, LogShape::Evaluation, LogShape::Samples, LogShape::MeanRatio};

std::string log_header(const TrainConfig& config, LogShape shape = LogShape::MeanRatio) {
  return std::string(kLogHeader) + (config.guided() ? kGuideLogColumns : "") +
         (shape >= LogShape::Evaluation ? kEvaluationLogColumns : "") +
         (shape >= LogShape::Samples ? kSamplesLogColumn : "") +
         (shape >= LogShape::MeanRatio ? kMeanRatioLogColumn : "");
}

// log.csv's samples cell of `step`: empty for a config written before the batch was resolved into it (batch 0).
std::string samples_cell(const TrainConfig& config, long step) {
  return config.batch > 0 && step >= 0 ? std::to_string(config.incident_samples(std::uint64_t(step))) : "";
}

// The shortest decimal that reads back as the same double: the logged MAPE is the one `compare --json` prints.
std::string shortest(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, v);
  return ec == std::errc() ? std::string(text, end) : std::to_string(v);
}

// A log written before today's columns existed gains them when its run resumes, so that every row has the header's
// fields: empty evaluation cells, and the samples its step had seen. A header of another shape is left alone.
void add_missing_columns(const fs::path& log_file, const TrainConfig& config) {
  const std::string text = read_input_text(log_file, "run log");
  const auto eol = text.find('\n');
  const std::string header = text.substr(0, eol);
  const auto shape = std::find_if(std::begin(kLogShapes), std::end(kLogShapes),
                                  [&](LogShape s) { return header == log_header(config, s); });
  if (shape == std::end(kLogShapes) || *shape == LogShape::MeanRatio) return;
  std::istringstream rows(eol == std::string::npos ? std::string() : text.substr(eol + 1));
  std::string out = log_header(config) + "\n", line;
  while (std::getline(rows, line)) {
    if (line.empty()) continue;
    out += line + (*shape < LogShape::Evaluation ? ",,," : "");
    if (*shape < LogShape::Samples) {
      long step = -1;
      const auto [end, ec] = std::from_chars(line.data(), line.data() + line.size(), step);
      out += "," + (ec == std::errc() && end != line.data() + line.size() && *end == ',' ? samples_cell(config, step)
                                                                                         : std::string());
    }
    out += ",\n";
  }
  write_record_atomically(log_file, out, "run log");
}

// A run killed (SIGKILL, power loss) while writing leaves write_atomically's temporary ("model.clr.tmp<pid>")
// beside the intact file. The caller holds the run's lock, so no live writer owns one: they are removed on resume
// rather than left to pile up, one per kill.
void remove_stale_temporaries(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    for (const fs::path& file :
         {RunDirectory::model_path(dir), RunDirectory::config_path(dir), RunDirectory::log_path(dir),
          RunDirectory::scene_path(dir), RunDirectory::evaluation_path(dir), RunDirectory::convergence_path(dir),
          RunDirectory::sessions_path(dir)}) {
      const std::string base = file.filename().string() + ".tmp";
      if (name.rfind(base, 0) == 0 && name.size() > base.size() &&
          name.find_first_not_of("0123456789", base.size()) == std::string::npos && entry.is_regular_file()) {
        std::error_code ec;
        fs::remove(entry.path(), ec);
      }
    }
  }
}

// The training time the run's sessions have logged: the `seconds` column of log.csv's last row (0 for a log with
// a header alone).
double logged_seconds(const fs::path& log_file) {
  std::istringstream log(read_input_text(log_file, "run log"));
  std::string line, last;
  long number = 0, last_number = 0;
  while (std::getline(log, line)) {
    ++number;
    if (!line.empty()) last = line, last_number = number;
  }
  if (last.empty() || !std::isdigit(static_cast<unsigned char>(last[0]))) return 0;
  const auto comma = last.find(',');
  const char* begin = comma == std::string::npos ? nullptr : last.c_str() + comma + 1;
  char* end = nullptr;
  const double seconds = begin ? std::strtod(begin, &end) : NAN;
  if (!begin || end == begin || (*end != ',' && *end != '\0') || !std::isfinite(seconds) || seconds < 0)
    throw InputError(log_file.string() + ":" + std::to_string(last_number) +
                     ": the seconds column is not a finite number ≥ 0");
  return seconds;
}

constexpr const char* kGuideBefore = "guide_before.";

// The checkpoint's free-form state string carries the seed and its scene's digest ("1 scene 0123…"), so that a
// model.clr copied out of its run, or into another one, is still checked against the scene it is given.
constexpr std::string_view kSceneMark = " scene ";

void write_model(const fs::path& dir, const TrainConfig& config, const scene::SceneFingerprint& scene,
                 const nn::Network& network, const nn::Network* guide, const nn::Network* guide_before = nullptr) {
  nn::Checkpoint c = network.checkpoint(std::to_string(config.seed) +
                                        (scene.digest.empty() ? "" : std::string(kSceneMark) + scene.digest));
  if (guide) guide->add_tensors(c, "guide.");
  if (guide_before) guide_before->add_parameter_tensors(c, kGuideBefore);
  nn::write_checkpoint(RunDirectory::model_path(dir).string(), c);
}

nlohmann::json scene_record(const scene::SceneFingerprint& scene) {
  nlohmann::json files = nlohmann::json::array();
  for (const auto& f : scene.files) files.push_back({{"name", f.name}, {"digest", f.digest}});
  nlohmann::json record = {{"scene", scene.scene.string()}, {"digest", scene.digest}, {"files", files}};
  if (!scene.parameters.empty()) record["parameters"] = scene.parameters;  // -D key=value
  return record;
}

void write_scene(const fs::path& dir, scene::SceneFingerprint scene) {
  scene.scene = fs::absolute(scene.scene).lexically_normal();
  write_record_atomically(RunDirectory::scene_path(dir), scene_record(scene).dump(2) + "\n", "run scene record");
}

// scene.json as written by write_scene; nullopt for a run written before runs recorded their scene.
std::optional<scene::SceneFingerprint> read_scene(const fs::path& dir) {
  const fs::path file = RunDirectory::scene_path(dir);
  if (!fs::exists(file) && !fs::is_symlink(file)) return std::nullopt;
  const nlohmann::json j = read_json_file(file, "run scene record");
  scene::SceneFingerprint f;
  try {
    f.scene = j.at("scene").get<std::string>();
    f.digest = j.at("digest").get<std::string>();
    if (!j.at("files").is_array()) throw InputError(file.string() + ": 'files' is not an array");
    for (const auto& e : j.at("files"))
      f.files.push_back({e.at("name").get<std::string>(), e.at("digest").get<std::string>()});
    if (j.contains("parameters")) f.parameters = j.at("parameters").get<std::map<std::string, std::string>>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not a run's scene record (" + clip(e.what()) + ")");
  }
  require_known_and_kept(j, scene_record(f), file.string());
  if (scene::files_digest(f.files, f.parameters) != f.digest)
    throw InputError(file.string() + ": its digest does not match the files it lists (the record was edited)");
  return f;
}

fs::path run_folder(const fs::path& run) { return fs::is_directory(run) ? run : run.parent_path(); }

}  // namespace

RunDirectory::RunDirectory(const fs::path& dir, bool create)
    : dir_(dir), lock_(std::make_unique<RunLock>(dir, create)) {}

RunDirectory RunDirectory::create(const fs::path& dir) {
  RunDirectory run(dir, true);
  if (!fs::is_empty(dir))
    throw InputError("run directory " + dir.string() + " is not empty (use --resume to continue it)");
  return run;
}

void RunDirectory::start(const TrainConfig& config, const scene::SceneFingerprint& scene) {
  config_ = config;
  scene_ = scene;
  write_scene(dir_, scene);
  write_record_atomically(config_path(dir_), nlohmann::json(config).dump(2) + "\n", "run config");
  write_record_atomically(log_path(dir_), log_header(config) + "\n", "run log");
}

RunDirectory RunDirectory::resume(const fs::path& dir, const scene::SceneFingerprint& scene) {
  RunDirectory run(dir, false);
  if (!fs::exists(model_path(dir))) throw InputError("--resume: no checkpoint " + model_path(dir).string());
  remove_stale_temporaries(dir);
  run.config_ = load_config(dir);
  run.seconds_trained_ = logged_seconds(log_path(dir));
  require_scene(dir, scene);  // before the log is touched: a run refused is left as it was
  add_missing_columns(log_path(dir), run.config_);
  run.scene_ = scene;
  return run;
}

TrainConfig RunDirectory::load_config(const fs::path& run) {
  const fs::path file = config_path(run);
  nlohmann::json saved = read_json_file(file, "run config");
  if (saved.is_object() && !saved.contains("method")) saved["method"] = to_string(Method::Nr);
  // Runs written before the lagged guide became the default drew their guided directions unlagged.
  if (saved.is_object() && !saved.contains("guide_lag")) saved["guide_lag"] = 0;
  // Runs written before next-event estimation joined the right-hand side trained without it.
  if (saved.is_object() && !saved.contains("nee")) saved["nee"] = false;
  // Runs written before the L2 start existed began in the relative residual.
  if (saved.is_object() && !saved.contains("relative_warmup")) saved["relative_warmup"] = 0.0;
  // Runs written before the power's ceiling existed reached power 1.
  if (saved.is_object() && !saved.contains("relative_power_max")) saved["relative_power_max"] = 1.0;
  // Runs written before the weight average existed rendered their parameters.
  if (saved.is_object() && !saved.contains("average_steps")) saved["average_steps"] = 0;
  try {
    return parse_train_config(saved);
  } catch (const InputError& e) {
    throw InputError(file.string() + ": " + e.what());
  }
}

std::string RunDirectory::log_line(const LogRow& r) const {
  char row[256];
  std::snprintf(row, sizeof row, "%ld,%.3f,%.6g,%.3f,%u,%.6g,%.4g", r.step, r.seconds, r.loss, r.lookups, r.non_finite,
                r.learning_rate, r.residual_power);
  std::string line = row;
  if (config_.guided()) {
    std::snprintf(row, sizeof row, ",%.6g,%.4f", r.guide_loss, r.guided_share);
    line += row;
  }
  const auto& e = r.evaluation;
  line += e ? "," + shortest(e->mape) + "," + shortest(e->mse) + "," + shortest(e->relmse) : ",,,";
  return line + "," + samples_cell(config_, r.step) + "," + (e ? shortest(e->mean_ratio) : "") + "\n";
}

void RunDirectory::append_log(const LogRow& r) const {
  std::ofstream out(log_path(dir_), std::ios::app);
  out << log_line(r);
  if (!out) throw std::runtime_error("cannot append to " + log_path(dir_).string());
}

void RunDirectory::replace_last_log_row(const LogRow& r) const {
  std::string text = read_input_text(log_path(dir_), "run log");
  while (!text.empty() && text.back() == '\n') text.pop_back();
  const auto last = text.rfind('\n');
  text.resize(last == std::string::npos ? 0 : last + 1);
  write_record_atomically(log_path(dir_), text + log_line(r), "run log");
}

void RunDirectory::save_model(const nn::Network& network, const nn::Network* guide,
                              const nn::Network* guide_before) const {
  write_model(dir_, config_, scene_, network, guide, guide_before);
}

void RunDirectory::write_snapshot(const fs::path& dir, const TrainConfig& config, const nn::Network& network,
                                  const nn::Network* guide) const {
  fs::create_directories(dir);
  write_scene(dir, scene_);
  write_record_atomically(config_path(dir), nlohmann::json(config).dump(2) + "\n", "run config");
  write_model(dir, config, scene_, network, guide);
}

std::vector<fs::path> RunDirectory::input_files(const fs::path& run) {
  const fs::path dir = run_folder(run);
  return {fs::is_directory(run) ? model_path(run) : run, config_path(dir), log_path(dir), scene_path(dir)};
}

double RunDirectory::training_seconds(const fs::path& run) { return logged_seconds(log_path(run_folder(run))); }

void RunDirectory::require_scene(const fs::path& run, const scene::SceneFingerprint& scene) {
  const auto recorded = read_scene(run_folder(run));
  if (recorded && !(*recorded == scene))
    throw InputError(run.string() + " was trained on " + recorded->scene.string() + " (scene digest " +
                     recorded->digest + "); " + scene.scene.string() + " is another scene (digest " + scene.digest +
                     ": " + scene::difference(*recorded, scene) + ")");
  // The model's own record of its scene, where its checkpoint carries one: a model.clr copied into another run
  // matches that run's scene.json but not its own scene. (A model that is no regular file, or no checkpoint, is
  // left to the checkpoint reader, whose message names the fault.)
  const fs::path model = fs::is_directory(run) ? model_path(run) : run;
  std::optional<std::string> carried;
  if (fs::is_regular_file(model)) try {
      const std::string state = nn::read_checkpoint(model.string()).rng_state;
      if (const auto at = state.find(kSceneMark); at != std::string::npos)
        carried = state.substr(at + kSceneMark.size());
    } catch (const InputError&) {
    }
  if (carried && *carried != scene.digest)
    throw InputError(model.string() + " was trained on another scene (digest " + *carried + ") than " +
                     scene.scene.string() + " (digest " + scene.digest + ")" +
                     (recorded ? ", though the scene record beside it matches: it was copied from another run" : ""));
  // A model with no record of its scene at all cannot be matched to one: adopting it under the scene given now
  // would answer with another scene's box and inputs.
  if (!recorded && !carried && fs::is_regular_file(model))
    throw InputError(model.string() + ": the model has no scene record (" + scene_path(run_folder(run)).string() +
                     "): the scene it was trained on cannot be checked; train it again");
}

std::unique_ptr<nn::Network> RunDirectory::load_radiance(cl::Context& ctx, const fs::path& run, bool to_train) {
  return load_network(ctx, fs::is_directory(run) ? model_path(run) : run, to_train);
}

std::unique_ptr<nn::Network> RunDirectory::load_guide(cl::Context& ctx, const fs::path& run) {
  const fs::path file = config_path(run);
  const nlohmann::json config = read_json_file(file, "run config");
  // Types checked before the values are read: nlohmann's type_error would otherwise end the command as a raw
  // library message with exit 1.
  if (!config.is_object() || (config.contains("method") && !config.at("method").is_string()))
    throw InputError(file.string() + ": not a run config ('method' must be a string)");
  if (config.value("method", to_string(Method::Nr)) != std::string(to_string(Method::Isnr)) ||
      !config.contains("guide"))
    throw InputError(run.string() + " was trained without an I-Module (method nr): there is no guide to read");
  nn::NetworkConfig guide_config;
  try {
    guide_config = nn::network_config_from_json(config.at("guide"));
    require_guide_network(guide_config);
  } catch (const InputError& e) {
    throw InputError(file.string() + ": guide: " + e.what());
  }
  return load_network(ctx, model_path(run), guide_config, "guide.");
}

std::unique_ptr<nn::Network> RunDirectory::load_guide_before(cl::Context& ctx, const fs::path& run,
                                                             const nn::NetworkConfig& guide) {
  const std::string file = model_path(run).string();
  const nn::Checkpoint c = nn::read_checkpoint(file);
  if (!c.has(std::string(kGuideBefore) + "mlp.params")) return nullptr;
  auto network = std::make_unique<nn::Network>(ctx, guide);
  network->restore_parameters(c, file, kGuideBefore);
  return network;
}

}  // namespace clr::radiosity
