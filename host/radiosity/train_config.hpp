#pragma once
// Every training setting, with the paper's defaults (ISNR §4.3: N = 4; the network's own defaults, Adam at 5e-3
// included, live under `network`, see nn/network.hpp). Read from
// `--config FILE.json`, overridden by CLI flags, validated, and saved as RUN_DIR/config.json so a run can be
// resumed and rendered with exactly the settings it was trained with.
#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace clr::radiosity {

// Isnr: the N-Module trained with directions from the one-sample mixture of the BSDF and the jointly trained
// I-Module (ISNR §4); Nr: BSDF sampling only (vanilla Neural Radiosity, the "w/o I-Module" ablation).
enum class Method { Isnr, Nr };
// The I-Module's loss: Improved KL (Eq. 18/20) or KL (Eq. 17).
enum class IsLoss { Ikl, Kl };
// Relative: r²/(sg(L)²+0.01)^power (TrainConfig::relative_power); L2: r² (paper Eq. 10).
enum class Residual { Relative, L2 };

// The modes' names in config.json, on the command line and in messages ("isnr", "ikl", "relative", …); parsing
// an unknown name is an InputError naming `key` and the names there are.
const char* to_string(Method m);
const char* to_string(IsLoss l);
const char* to_string(Residual r);
Method parse_method(std::string_view text, std::string_view key = "method");
IsLoss parse_is_loss(std::string_view text, std::string_view key = "is_loss");
Residual parse_residual(std::string_view text, std::string_view key = "residual");
void to_json(nlohmann::json& j, Method m);
void from_json(const nlohmann::json& j, Method& m);
void to_json(nlohmann::json& j, IsLoss l);
void from_json(const nlohmann::json& j, IsLoss& l);
void to_json(nlohmann::json& j, Residual r);
void from_json(const nlohmann::json& j, Residual& r);

struct TrainConfig {
  Method method = Method::Isnr;
  IsLoss is_loss = IsLoss::Ikl;
  double bsdf_fraction = 0.5;  // c in p̃ = c·p_bsdf + (1 − c)·q (isnr); the defensive share keeps variance bounded
  // The guide's warm-up (isnr): over this fraction of the budget the guided share 1 − c rises linearly from 0 to
  // 1 − bsdf_fraction. The I-Module learns from the BSDF's samples meanwhile; an untrained guide only adds
  // variance, which the N-Module then fits.
  double guide_warmup = 0.1;
  // How many I-Module updates behind the step its guided directions are (isnr). 0: drawn from the I-Module after the
  // previous step's update, so the host traces them only once that update is done (the step's one blocking read).
  // 1: drawn from the I-Module before the previous step's update — step k+1's directions are drawn and read back
  // early in step k, and the host traces them while the device runs step k's networks (docs/design.md §2). The
  // estimate stays unbiased either way: p̃ is the density the directions were drawn from. 1 by default: it trained
  // as well as 0 within the seeds' spread on the Cornell box and Veach Bidir (docs/results/isnr.md).
  int guide_lag = 1;
  Residual residual = Residual::Relative;
  // Next-event estimation in the right-hand side (docs/method.md, "Next-event estimation"): one light sample per
  // incident sample, drawn by the path tracer's light sampler (area lights, the environment), weighted by the power
  // heuristic against the BSDF's density, beside the directions; the emission those directions hit carries the
  // complementary weight. false: the paper's estimator, which finds emitters only by the directions it draws.
  bool nee = true;
  int samples = 4;     // N incident directions per point
  int batch = 0;       // M points per step; 0 = chosen for the device
  long steps = 0;      // stop after this many steps in total (0 = no step limit)
  double minutes = 0;  // stop after this much wall time in this session (0 = no time limit)
  std::uint64_t seed = 1;
  // The budget preset the run was set up with ("" for none; radiosity/preset.hpp): its choices are already in
  // the settings here, the name records where they came from.
  std::string preset;
  // Learning-rate annealing over the run's budget (--steps, else this session's --minutes): the rate holds until
  // the fraction `anneal_start` of the budget is spent, then falls geometrically to `anneal_final` × itself at the
  // end. A noisy Monte Carlo target needs it: at a constant rate the fit keeps the noise of the last steps.
  double anneal_start = 0.5;
  double anneal_final = 0.05;
  // A linear learning-rate warm-up over the first this many steps (0: none): Adam's first steps move every
  // parameter by about the full rate whatever the gradient's size, and from the dark start they overshoot the
  // image's scale (docs/method.md, "The start").
  long learning_rate_warmup = 0;
  // The model rendered and evaluated is an exponential moving average of the N-Module's parameters over about this
  // many steps (0: the parameters themselves). Training steps the parameters as before; the average smooths the
  // swings that the estimator's noise drives them through (docs/method.md, "The weight average"). Early steps
  // average over fewer: the weight of the newest parameters is max(1/average_steps, 9/(10 + step)). 100: on Veach
  // Ajar it held the image's mean within 0.89–1.41 of the reference's from a fifth of a 1500-step budget on
  // (0.83–1.39 without) at no cost in MAPE.
  long average_steps = 100;
  // The relative residual's denominator power falls linearly from 1 to 0 (plain L2) by the fraction
  // `relative_fade_end` of the budget, as the NR authors' code can; 0 keeps it at 1. The relative residual weighs
  // dark regions like bright ones, but it barely resists a solution scaled up as a whole (its pull is 2r/L²) and
  // the emitters that anchor the scale are found rarely: on Veach Ajar it ran away to a white image. The L2 part
  // pulls the scale back; reaching plain L2 only at the end (rather than by 80 % of the budget) keeps enough of
  // the relative pull on dark regions for short budgets (docs/method.md; docs/results/nr-training.md).
  double relative_fade_end = 1.0;
  // A start in plain L2: the power rises from 0 to the fade's value over this fraction of the budget (0: the
  // relative residual from the first step). On Veach Ajar it moved the relative residual's early runaway to where
  // the power neared 1 rather than removing it (docs/method.md): a setting, not the default.
  double relative_warmup = 0.0;
  // The power's ceiling: the schedule above times this. At 1 the relative residual is scale-free — a solution
  // scaled by k costs the same at large k — and on Veach Ajar it ran away (the image 10–400× too bright) while the
  // power was near 1; below 1 the loss grows with the scale. 0.5 ended no worse than the uncapped schedule on the
  // four shared scenes (docs/method.md).
  double relative_power_max = 0.5;
  long log_every = 25;  // rows of log.csv
  long checkpoint_every = 500;
  // Overrides of the N-Module's settings (encoder, MLP, Adam, gemm backend) as a JSON merge patch over the
  // scene's defaults; a run's config.json stores the complete result.
  nlohmann::json network = nlohmann::json::object();
  // The same for the I-Module (isnr), over i_module_config; its Adam learning rate is guide.adam.learning_rate.
  nlohmann::json guide = nlohmann::json::object();

  bool guided() const { return method == Method::Isnr; }

  // The incident samples (points × N directions; next-event estimation's light samples not counted) a run has
  // trained on after `steps_done`: the unit in which runs of other batches and N compare. 0 while the batch is
  // unresolved.
  std::uint64_t incident_samples(std::uint64_t steps_done) const {
    return steps_done * std::uint64_t(std::max(batch, 0)) * std::uint64_t(std::max(samples, 0));
  }

  // The weight average's decay after `steps_done` steps (the newest parameters get 1 − this).
  double average_decay(long steps_done) const {
    return std::min(1.0 - 1.0 / double(std::max(average_steps, 1L)), double(1 + steps_done) / double(10 + steps_done));
  }

  // The factor on the learning rate once `progress` ∈ [0, 1] of the budget and `steps_done` steps are spent.
  double learning_rate_scale(double progress, long steps_done) const;

  // c once `progress` of the budget is spent (the warm-up's ramp, then bsdf_fraction).
  double bsdf_fraction_at(double progress) const;

  // The power of the residual's denominator once `progress` of the budget is spent (0 for plain L2).
  double relative_power(double progress) const;

  // Throws InputError naming the first impossible setting (e.g. "samples must be ≥ 1, got 0").
  void validate() const;

  // Drops from `network` and `guide` what a run derived from its scene — the hash grids' bounding box, which inputs
  // vary, the radiance unit — so that another scene derives its own: a run's config.json reused for another scene.
  void forget_scene();
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(TrainConfig, method, is_loss, bsdf_fraction, guide_warmup, guide_lag,
                                                residual, nee, samples, batch, steps, minutes, seed, preset,
                                                anneal_start, anneal_final, learning_rate_warmup, average_steps,
                                                relative_fade_end, relative_warmup, relative_power_max, log_every,
                                                checkpoint_every, network, guide)

// Applies the keys of `j` over `base`. An unknown key or a value of the wrong type is an InputError naming the
// key (a misspelt key must not be silently ignored); the result is validated.
TrainConfig parse_train_config(const nlohmann::json& j, const TrainConfig& base = {});

TrainConfig load_train_config(const std::string& path);

}  // namespace clr::radiosity
