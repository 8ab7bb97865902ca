#include "radiosity/train_config.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <type_traits>

#include "common/enum_names.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "nn/network.hpp"
#include "radiosity/preset.hpp"

namespace clr::radiosity {
namespace {

template <typename T>
void require(bool ok, const char* name, const T& value, const char* rule) {
  if (ok) return;
  std::string got;
  if constexpr (std::is_arithmetic_v<T>) {
    std::ostringstream text;  // JSON would print NaN and infinities as null
    text << std::setprecision(9) << value;
    got = text.str();
  } else {
    got = clip(nlohmann::json(value).dump());
  }
  throw InputError(std::string(name) + " must be " + rule + ", got " + got);
}

// Each incident sample of a step is one row of kRawInputs = 13 floats in one device buffer; 2^24 rows (872 MB)
// keep that buffer under PoCL's 1 GiB cap on a single allocation (docs/design.md §5).
constexpr long long kMaxIncidentSamples = 1LL << 24;

template <typename E, std::size_t N>
E parse_name(std::string_view text, std::string_view key, const EnumNames<E, N>& names) {
  if (const auto value = value_named(text, names)) return *value;
  throw InputError(std::string(key) + " must be " + choices(names) + ", got \"" + std::string(text.substr(0, 64)) +
                   "\"");
}

constexpr EnumNames<Method, 2> kMethods = {{Method::Isnr, "isnr"}, {Method::Nr, "nr"}};
constexpr EnumNames<IsLoss, 2> kIsLosses = {{IsLoss::Ikl, "ikl"}, {IsLoss::Kl, "kl"}};
constexpr EnumNames<Residual, 2> kResiduals = {{Residual::Relative, "relative"}, {Residual::L2, "l2"}};

// A mode in JSON is one of its names; anything else (another type included) is an InputError naming the key.
template <typename E, std::size_t N>
E from_json_name(const nlohmann::json& j, const char* key, const EnumNames<E, N>& names) {
  if (!j.is_string()) return parse_name(j.dump(), key, names);
  return parse_name(j.get_ref<const std::string&>(), key, names);
}

}  // namespace

const char* to_string(Method m) { return name_of(m, kMethods); }
const char* to_string(IsLoss l) { return name_of(l, kIsLosses); }
const char* to_string(Residual r) { return name_of(r, kResiduals); }
Method parse_method(std::string_view text, std::string_view key) { return parse_name(text, key, kMethods); }
IsLoss parse_is_loss(std::string_view text, std::string_view key) { return parse_name(text, key, kIsLosses); }
Residual parse_residual(std::string_view text, std::string_view key) { return parse_name(text, key, kResiduals); }
void to_json(nlohmann::json& j, Method m) { j = to_string(m); }
void from_json(const nlohmann::json& j, Method& m) { m = from_json_name(j, "method", kMethods); }
void to_json(nlohmann::json& j, IsLoss l) { j = to_string(l); }
void from_json(const nlohmann::json& j, IsLoss& l) { l = from_json_name(j, "is_loss", kIsLosses); }
void to_json(nlohmann::json& j, Residual r) { j = to_string(r); }
void from_json(const nlohmann::json& j, Residual& r) { r = from_json_name(j, "residual", kResiduals); }

void TrainConfig::validate() const {
  // c = 0 would never draw a delta lobe (its share of p̃ is c): the estimate would lose that light.
  require(bsdf_fraction > 0 && bsdf_fraction <= 1, "bsdf_fraction", bsdf_fraction, "in (0, 1]");
  require(guide_warmup >= 0 && guide_warmup <= 1, "guide_warmup", guide_warmup, "in [0, 1]");
  require(guide_lag == 0 || guide_lag == 1, "guide_lag", guide_lag, "0 or 1");
  require(samples >= 1 && samples <= 1024, "samples", samples, "in [1, 1024]");
  require(batch >= 0 && batch <= (1 << 22), "batch", batch, "in [1, 4194304] (0 = automatic)");
  require(std::max(batch, 1) * static_cast<long long>(samples) <= kMaxIncidentSamples, "batch × samples",
          std::max(batch, 1) * static_cast<long long>(samples), "at most 2^24 incident samples per step");
  const auto& presets = preset_names();
  require(preset.empty() || std::find(presets.begin(), presets.end(), preset) != presets.end(), "preset", preset,
          "preview, balanced or quality");
  require(steps >= 0, "steps", steps, ">= 0");
  require(minutes >= 0 && std::isfinite(minutes), "minutes", minutes, ">= 0");
  require(anneal_start >= 0 && anneal_start <= 1, "anneal_start", anneal_start, "in [0, 1]");
  require(anneal_final > 0 && anneal_final <= 1, "anneal_final", anneal_final, "in (0, 1]");
  require(learning_rate_warmup >= 0, "learning_rate_warmup", learning_rate_warmup, ">= 0");
  require(average_steps >= 0, "average_steps", average_steps, ">= 0");
  require(relative_fade_end >= 0 && relative_fade_end <= 1, "relative_fade_end", relative_fade_end, "in [0, 1]");
  require(relative_warmup >= 0 && relative_warmup <= 1, "relative_warmup", relative_warmup, "in [0, 1]");
  require(relative_power_max >= 0 && relative_power_max <= 1, "relative_power_max", relative_power_max, "in [0, 1]");
  require(log_every >= 1, "log_every", log_every, ">= 1");
  require(checkpoint_every >= 1, "checkpoint_every", checkpoint_every, ">= 1");
  require(network.is_object(), "network", network, "an object");
  require(guide.is_object(), "guide", guide, "an object");
  // The modules' patches are checked now, not once a scene has been loaded: both modules have the keys of a
  // default network.
  for (const auto& [key, patch] : {std::pair{"network", &network}, std::pair{"guide", &guide}}) try {
      nn::merge_patch(nn::NetworkConfig{}, *patch);
    } catch (const InputError& e) {
      throw InputError(std::string(key) + ": " + e.what());
    }
}

void TrainConfig::forget_scene() {
  for (nlohmann::json* module : {&network, &guide}) {
    if (!module->is_object()) continue;
    module->erase("output_scale");
    const auto encoder = module->find("encoder");
    if (encoder == module->end() || !encoder->is_object()) continue;
    encoder->erase("albedo");
    encoder->erase("roughness");
    const auto grid = encoder->find("grid");
    if (grid == encoder->end() || !grid->is_object()) continue;
    grid->erase("bbox_lo");
    grid->erase("bbox_hi");
  }
}

double TrainConfig::learning_rate_scale(double progress, long steps_done) const {
  const double warm = steps_done < learning_rate_warmup ? double(steps_done + 1) / double(learning_rate_warmup) : 1.0;
  if (progress <= anneal_start || anneal_start >= 1) return warm;
  return warm * std::pow(anneal_final, (std::min(progress, 1.0) - anneal_start) / (1.0 - anneal_start));
}

double TrainConfig::bsdf_fraction_at(double progress) const {
  if (progress >= guide_warmup) return bsdf_fraction;
  return 1.0 - (1.0 - bsdf_fraction) * std::max(0.0, progress) / guide_warmup;
}

double TrainConfig::relative_power(double progress) const {
  if (residual == Residual::L2) return 0.0;
  const double fade = relative_fade_end <= 0 ? 1.0 : std::max(0.0, 1.0 - progress / relative_fade_end);
  const double ramp = relative_warmup > 0 && progress < relative_warmup ? std::max(0.0, progress) / relative_warmup : 1;
  return relative_power_max * fade * ramp;
}

TrainConfig parse_train_config(const nlohmann::json& j, const TrainConfig& base) {
  if (!j.is_object()) throw InputError("training config must be a JSON object, got " + clip(j.dump()));
  const nlohmann::json defaults = base;
  for (const auto& [key, value] : j.items()) {
    if (!defaults.contains(key)) throw InputError("unknown training config key '" + clip(key) + "'");
    const auto& want = defaults[key];
    const bool same_kind = (want.is_number() && value.is_number()) || want.type() == value.type();
    const bool integral_ok = !want.is_number_integer() || value.is_number_integer() ||
                             (value.is_number_unsigned() && want.is_number_unsigned());
    if (!same_kind || !integral_ok)
      throw InputError("training config key '" + key + "' should be a " + want.type_name() + ", got " +
                       clip(value.dump()));
  }
  nlohmann::json merged = defaults;
  merged.update(j);
  TrainConfig c = merged.get<TrainConfig>();
  require_known_and_kept(j, nlohmann::json(c), "training config");
  c.validate();
  return c;
}

TrainConfig load_train_config(const std::string& path) {
  const nlohmann::json j = read_json_file(path, "config file");
  try {
    return parse_train_config(j);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace clr::radiosity
