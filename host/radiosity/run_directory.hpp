#pragma once
// RUN_DIR, the files of one training: config.json (every setting, the networks' included), log.csv (a row per log
// interval), model.clr (both modules' checkpoint), scene.json (the fingerprint of the scene it models: every
// reader of the run checks the scene it is given against it) and sessions.json (what trained it, session by session).
// The file names live here alone. A RunDirectory is the one writer of a run: it holds the directory's lock
// (common/run_lock.hpp) for as long as it lives. Reading a run (render, residual, guide, a sweep's snapshots) needs no
// lock: the static readers below.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cl/context.hpp"
#include "common/run_lock.hpp"
#include "image/image.hpp"
#include "nn/network.hpp"
#include "radiosity/train_config.hpp"
#include "scene/fingerprint.hpp"

namespace clr::radiosity {

// One row of log.csv: the means over the steps since the previous row.
struct LogRow {
  long step = 0;
  double seconds = 0;  // training time over every session of the run
  double loss = 0;     // the N-Module's mean residual loss
  double lookups = 0;  // share of incident samples that needed the network
  std::uint32_t non_finite = 0;
  double learning_rate = 0;   // the N-Module's, after the schedule
  double residual_power = 0;  // the relative residual's denominator power (0: plain L2)
  // ISNR runs only.
  double guide_loss = 0;
  double guided_share = 0;  // share of incident samples drawn from the I-Module's mixture
  // The model at this step against a reference (train --reference, convergence.hpp); empty columns without one.
  std::optional<image::Metrics> evaluation = std::nullopt;
};

class RunDirectory {
 public:
  static std::filesystem::path config_path(const std::filesystem::path& dir) { return dir / "config.json"; }
  static std::filesystem::path log_path(const std::filesystem::path& dir) { return dir / "log.csv"; }
  static std::filesystem::path model_path(const std::filesystem::path& dir) { return dir / "model.clr"; }
  static std::filesystem::path scene_path(const std::filesystem::path& dir) { return dir / "scene.json"; }
  // What `train --reference` adds (convergence.hpp): the record of what its log columns measure, and their figure.
  static std::filesystem::path evaluation_path(const std::filesystem::path& dir) { return dir / "evaluation.json"; }
  static std::filesystem::path convergence_path(const std::filesystem::path& dir) { return dir / "convergence.svg"; }
  // What trained the run, one entry per session: commit, device, peak memory, the preset's reasons
  // (session_record.hpp). Written by `train` after each session, not part of the settings.
  static std::filesystem::path sessions_path(const std::filesystem::path& dir) { return dir / "sessions.json"; }

  // A new run: `dir` must be absent or empty. Locks and creates it; start() writes its first files once the
  // settings are complete.
  static RunDirectory create(const std::filesystem::path& dir);
  // config.json, scene.json and log.csv's header.
  void start(const TrainConfig& config, const scene::SceneFingerprint& scene);
  // An existing run of `scene` (else InputError naming both scenes): locks it, removes what killed writers left
  // behind, reads its settings (a run written before ISNR existed has no method: it was NR) and the training time
  // of its sessions so far (log.csv's last row).
  static RunDirectory resume(const std::filesystem::path& dir, const scene::SceneFingerprint& scene);

  const std::filesystem::path& path() const { return dir_; }
  const TrainConfig& config() const { return config_; }
  const scene::SceneFingerprint& scene() const { return scene_; }
  double seconds_trained() const { return seconds_trained_; }

  void append_log(const LogRow& row) const;
  // Replaces log.csv's last row by `row` (atomically: the whole file is rewritten): the run's last step, logged
  // before anyone knew it was the last, gains its evaluation.
  void replace_last_log_row(const LogRow& row) const;
  // model.clr, written atomically: the previous one stays intact until the new one is complete. `guide_before`: the
  // lagged guide's I-Module before its last update (parameters only), which the next step draws from.
  void save_model(const nn::Network& network, const nn::Network* guide,
                  const nn::Network* guide_before = nullptr) const;
  // The networks as they are now, as a run directory of their own (config.json + model.clr) that render, residual
  // and guide read: a sweep's snapshot of the run at one budget.
  void write_snapshot(const std::filesystem::path& dir, const TrainConfig& config, const nn::Network& network,
                      const nn::Network* guide) const;

  // InputError naming both scenes when `run` (a run directory or its model.clr) was trained on another scene than
  // `scene`: its bounding box, inputs and light would silently be taken for this one's. A run written before runs
  // recorded their scene (no scene.json) is not checked.
  static void require_scene(const std::filesystem::path& run, const scene::SceneFingerprint& scene);

  // The files a reader of `run` (a run directory or its model.clr) reads: inputs no output may replace.
  static std::vector<std::filesystem::path> input_files(const std::filesystem::path& run);
  // The N-Module of a run (`run` a run directory or its model.clr): the model it renders (trained_model.hpp's
  // load_network), or with `to_train` the state training resumes from.
  static std::unique_ptr<nn::Network> load_radiance(cl::Context& ctx, const std::filesystem::path& run,
                                                    bool to_train = false);
  // The I-Module of an ISNR run: its config from config.json, its tensors from model.clr. InputError when the run
  // was trained without one (method nr) or its files are missing or damaged.
  static std::unique_ptr<nn::Network> load_guide(cl::Context& ctx, const std::filesystem::path& run);
  // The lagged guide's I-Module before its last update, where model.clr holds it (null where it does not: a run
  // without the lag, or written before it existed), as a network of the guide's config.
  static std::unique_ptr<nn::Network> load_guide_before(cl::Context& ctx, const std::filesystem::path& run,
                                                        const nn::NetworkConfig& guide);
  // The run's settings as saved (InputError naming the file when it is missing or malformed).
  static TrainConfig load_config(const std::filesystem::path& run);
  // The training time of every session of `run` (a run directory or its model.clr): log.csv's last row.
  static double training_seconds(const std::filesystem::path& run);

 private:
  RunDirectory(const std::filesystem::path& dir, bool create);
  std::string log_line(const LogRow& row) const;
  std::filesystem::path dir_;
  std::unique_ptr<RunLock> lock_;
  TrainConfig config_;
  scene::SceneFingerprint scene_;
  double seconds_trained_ = 0;
};

}  // namespace clr::radiosity
