#include "radiosity/train_config.hpp"

#include <cmath>
#include <fstream>
#include <set>

#include "common/error.hpp"

namespace clr::radiosity {
namespace {

template <typename T>
void require(bool ok, const char* name, const T& value, const char* rule) {
  if (!ok) throw InputError(std::string(name) + " must be " + rule + ", got " + nlohmann::json(value).dump());
}

}  // namespace

void TrainConfig::validate() const {
  require(method == "nr" || method == "isnr", "method", method, "nr or isnr");
  require(is_loss == "ikl" || is_loss == "kl", "is_loss", is_loss, "ikl or kl");
  require(residual == "relative" || residual == "l2", "residual", residual, "relative or l2");
  require(samples >= 1 && samples <= 1024, "samples", samples, "in [1, 1024]");
  require(batch >= 0 && batch <= (1 << 22), "batch", batch, "in [1, 4194304] (0 = automatic)");
  require(steps >= 0, "steps", steps, ">= 0");
  require(minutes >= 0 && std::isfinite(minutes), "minutes", minutes, ">= 0");
  require(learning_rate > 0 && std::isfinite(learning_rate), "learning_rate", learning_rate, "> 0");
  require(lr_decay > 0 && lr_decay <= 1, "lr_decay", lr_decay, "in (0, 1]");
  require(lr_decay_steps >= 1, "lr_decay_steps", lr_decay_steps, ">= 1");
  require(bsdf_fraction >= 0 && bsdf_fraction <= 1, "bsdf_fraction", bsdf_fraction, "in [0, 1]");
  require(log_every >= 1, "log_every", log_every, ">= 1");
  require(checkpoint_every >= 1, "checkpoint_every", checkpoint_every, ">= 1");
  require(network.is_object(), "network", network, "an object");
}

#define CLR_TRAIN_CONFIG_FIELDS(X)                                                                           \
  X(method)                                                                                                  \
  X(is_loss)                                                                                                 \
  X(residual) X(samples) X(batch) X(steps) X(minutes) X(seed) X(learning_rate) X(lr_decay) X(lr_decay_steps) \
      X(bsdf_fraction) X(log_every) X(checkpoint_every) X(network)

void to_json(nlohmann::json& j, const TrainConfig& c) {
#define CLR_PUT(f) j[#f] = c.f;
  j = nlohmann::json::object();
  CLR_TRAIN_CONFIG_FIELDS(CLR_PUT)
#undef CLR_PUT
}

void from_json(const nlohmann::json& j, TrainConfig& c) {
  if (!j.is_object()) throw InputError("training config must be a JSON object");
  std::set<std::string> known;
#define CLR_GET(f)                                                                                          \
  known.insert(#f);                                                                                         \
  if (j.contains(#f)) try {                                                                                 \
      j.at(#f).get_to(c.f);                                                                                 \
    } catch (const nlohmann::json::exception&) {                                                            \
      throw InputError(std::string("training config key '" #f "' has the wrong type: ") + j.at(#f).dump()); \
    }
  CLR_TRAIN_CONFIG_FIELDS(CLR_GET)
#undef CLR_GET
  for (const auto& [key, value] : j.items())
    if (!known.count(key)) throw InputError("unknown training config key '" + key + "'");
}

TrainConfig load_train_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("config file not found: " + path);
  TrainConfig c;
  try {
    from_json(nlohmann::json::parse(in), c);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError("malformed JSON in " + path + ": " + e.what());
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  c.validate();
  return c;
}

}  // namespace clr::radiosity
