#include "sweep/sweep_plan.hpp"

#include <algorithm>
#include <cstdio>

#include "common/error.hpp"

namespace clr::sweep {

std::string Configuration::name() const {
  return method + "-n" + std::to_string(samples) + "-seed" + std::to_string(seed);
}

radiosity::TrainConfig Configuration::train_config(const radiosity::TrainConfig& base, double minutes) const {
  radiosity::TrainConfig c = base;
  c.method = guided() ? radiosity::Method::Isnr : radiosity::Method::Nr;
  if (guided()) c.is_loss = radiosity::parse_is_loss(method.substr(5), "--methods");
  c.samples = samples;
  c.seed = seed;
  c.steps = 0;
  c.minutes = minutes;
  c.validate();
  return c;
}

void check_method(const std::string& method) {
  if (method != "nr" && method != "isnr-kl" && method != "isnr-ikl")
    throw InputError("--methods: unknown method '" + method + "' (nr, isnr-kl or isnr-ikl)");
}

std::vector<Configuration> plan_configurations(const std::vector<std::string>& methods, const std::vector<int>& samples,
                                               int seeds) {
  std::vector<std::string> ordered = methods;
  std::stable_partition(ordered.begin(), ordered.end(), [](const std::string& m) { return m != "nr"; });
  std::vector<Configuration> plan;
  for (const auto& m : ordered)
    for (int n : samples)
      for (int seed = 1; seed <= seeds; ++seed) plan.push_back({m, n, std::uint64_t(seed)});
  return plan;
}

std::string budget_label(double minutes) {
  char s[32];
  std::snprintf(s, sizeof s, "%gmin", minutes);
  return s;
}

}  // namespace clr::sweep
