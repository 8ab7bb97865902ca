#include "radiosity/preset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.hpp"
#include "nn/hashgrid.hpp"
#include "nn/network.hpp"
#include "radiosity/trainer.hpp"

namespace clr::radiosity {
namespace {

struct Preset {
  const char* name;
  double minutes;   // the budget when none is given
  int cpu_batch;    // 0: the device's default (default_batch)
  int samples;      // N
  const char* why;  // the measurements behind the batch, the width and N (docs/presets.md)
};

// The hash table of every preset, at most (smaller where the scene's surfaces need fewer entries): at 1000 steps
// 2^16 was worse and 2^20 no better than 2^18 on the Cornell box and Veach Bidir.
constexpr std::size_t kMaxLog2Table = 18;

constexpr Preset kPresets[] = {
    {"preview", 1.0, 2048, 4,
     "at a 1-minute budget batch 2048 beat 4096 on CPUs (the Cornell box and Veach Bidir: more steps average "
     "the noise down), and width 128 lost to 256 (fewer parameters learn less per step than the extra steps gain)"},
    {"balanced", 2.0, 0, 4,
     "the defaults: from 2 minutes on, batch 4096 beat 2048 on CPUs; width 256 on CPUs beat 512 at 2-10 minutes; "
     "the paper's batch and width on GPUs"},
    {"quality", 10.0, 0, 4,
     "the defaults, for 10 minutes: width 256 on CPUs still beat 512 there; N = 32 took a third of the steps and "
     "was no better for ISNR on Veach Bidir at 5 and 10 minutes (clradiosity sweep)"},
};

// Hash-table entries the modelled surfaces occupy at the grid's finest level: a surface crosses about
// 2·area/cell² vertices there (two layers about a plane), with the area in units of the box the grid spans.
double surface_vertices(const SceneInputs& scene, const nn::HashGridConfig& grid) {
  const double ex = scene.hi[0] - scene.lo[0], ey = scene.hi[1] - scene.lo[1], ez = scene.hi[2] - scene.lo[2];
  const double unit_area = scene.area / std::cbrt(ex * ex * ey * ey * ez * ez);
  const double finest = nn::hashgrid_levels(grid).back().resolution;
  return 2.0 * unit_area * finest * finest;
}

// The paper's settings (ISNR §4.3 "Implementation", §5.1 "Comparisons"); docs/presets.md lists what it states and
// what it leaves open.
struct PaperSettings {
  static constexpr std::size_t width = 512;       // §4.3: "four linear layers, each with a width of 512"
  static constexpr int samples = 4;               // §5.1: N = 4 (Table 1) and N = 32 (Table 2)
  static constexpr double learning_rate = 0.005;  // §4.3: "a learning rate of 0.005 using the Adam optimizer"
  // Table 1's most common step count (Modern Hall, Wooden Staircase, Bathroom; the eight scenes took 21k–30k).
  static constexpr long steps = 25000;
  // Not stated: the points per step. 16384 = 2^14, the project's GPU default: Table 1 and 2's memory grows from
  // ~2 GB at N = 4 to ~12 GB at N = 32, about 0.36 GB per incident sample a point, ~22 KB per sample at M = 2^14 —
  // the order of a 512-wide MLP's float activations with autograd's copies; a batch many times larger or smaller
  // would not fit that figure. An estimate, not a statement of the paper.
  static constexpr int batch = 16384;
  // Not stated beyond "a multi-resolution hash grid [23]": that work's (Müller et al. 2022, Table 1) L = 16
  // levels, F = 2 features, T = 2^19 entries a level, N_min = 16, and N_max = 2048 (its setting for a unit-cube
  // NeRF scene; the grid spans the scene's box here), so b = (N_max / N_min)^(1 / (L − 1)).
  static constexpr std::size_t levels = 16, features = 2, log2_table = 19, base_resolution = 16;
  static constexpr double finest_resolution = 2048;
};

std::vector<std::string> apply_paper(TrainConfig& config, const cl::DeviceInfo& device) {
  using P = PaperSettings;
  std::vector<std::string> why;
  char line[768];
  config.preset = kPaperPreset;
  if (config.steps == 0 && config.minutes == 0) {
    config.steps = P::steps;
    std::snprintf(line, sizeof line,
                  "budget %ld steps (Table 1's most common count; give --steps for a scene's own: "
                  "bench/paper/paper.json)",
                  P::steps);
    why.emplace_back(line);
  }
  config.batch = P::batch;
  config.samples = P::samples;
  config.residual = Residual::L2;
  config.average_steps = 0;  // the paper renders the network it trained
  config.network["width"] = P::width;
  config.network["adam"]["learning_rate"] = P::learning_rate;
  config.guide["adam"]["learning_rate"] = P::learning_rate;
  const double growth = std::pow(P::finest_resolution / double(P::base_resolution), 1.0 / double(P::levels - 1));
  config.network["encoder"]["grid"] = {{"levels", P::levels},
                                       {"features", P::features},
                                       {"log2_table", P::log2_table},
                                       {"base_resolution", P::base_resolution},
                                       {"growth", growth}};
  std::snprintf(
      line, sizeof line,
      "N-Module width %zu, N = %d, Adam %g for both modules, the plain L2 residual (ISNR §4.3, §5.1, Eq. 10), the "
      "trained parameters rendered (no weight average); "
      "batch %d, which the paper does not state (docs/presets.md: why this one)%s",
      P::width, P::samples, P::learning_rate, P::batch,
      device.type == cl::DeviceType::Gpu
          ? ""
          : "; on a CPU device these GPU-scale settings make steps of seconds (for CPU scale, train without "
            "the preset)");
  why.emplace_back(line);
  std::snprintf(line, sizeof line,
                "hash grid of the cited work (Müller et al. 2022): %zu levels x %zu features, 2^%zu entries, "
                "resolution %zu to %g (growth %.4f); the paper gives no parameters",
                P::levels, P::features, P::log2_table, P::base_resolution, P::finest_resolution, growth);
  why.emplace_back(line);
  return why;
}

}  // namespace

const std::vector<std::string>& budget_preset_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& p : kPresets) v.emplace_back(p.name);
    return v;
  }();
  return names;
}

const std::vector<std::string>& preset_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v = budget_preset_names();
    v.emplace_back(kPaperPreset);
    return v;
  }();
  return names;
}

std::vector<std::string> apply_preset(const std::string& name, TrainConfig& config, const SceneInputs& scene,
                                      const cl::DeviceInfo& device) {
  const auto* p =
      std::find_if(std::begin(kPresets), std::end(kPresets), [&](const Preset& r) { return name == r.name; });
  if (name == kPaperPreset) return apply_paper(config, device);
  if (p == std::end(kPresets))
    throw InputError("unknown preset '" + name + "' (preview, balanced, quality or " + kPaperPreset + ")");
  std::vector<std::string> why;
  char line[512];
  config.preset = name;
  if (config.steps == 0 && config.minutes == 0) {
    config.minutes = p->minutes;
    std::snprintf(line, sizeof line, "budget %g min (no --steps or --minutes given)", p->minutes);
    why.emplace_back(line);
  }
  // GPUs take the defaults (the paper's batch and width): no GPU has measured other choices yet.
  const bool gpu = device.type == cl::DeviceType::Gpu;
  config.batch = gpu || p->cpu_batch == 0 ? default_batch(device) : p->cpu_batch;
  config.samples = p->samples;
  const std::size_t width = default_width(device);
  config.network["width"] = width;
  std::snprintf(line, sizeof line, "batch %d x N %d, N-Module width %zu on a %s: %s", config.batch, config.samples,
                width, gpu ? "GPU" : "CPU", p->why);
  why.emplace_back(line);

  // The table: the preset's size, or the power of two that holds every surface vertex of the finest level when
  // that is smaller (small scenes); a table larger than what the surfaces touch only costs memory.
  const nn::HashGridConfig grid = *nn::n_module_config(scene.lo, scene.hi).encoder.grid;
  const double need = surface_vertices(scene, grid);
  const auto log2_table =
      std::clamp<std::size_t>(std::size_t(std::ceil(std::log2(std::max(need, 1.0)))), 10, kMaxLog2Table);
  config.network["encoder"]["grid"]["log2_table"] = log2_table;
  std::snprintf(line, sizeof line,
                "hash table 2^%zu entries a level: the surfaces cross ~%.3g vertices at the finest level; 2^16 was "
                "worse and 2^20 no better than 2^18 at equal steps",
                log2_table, need);
  why.emplace_back(line);
  return why;
}

}  // namespace clr::radiosity
