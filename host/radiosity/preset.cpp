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

}  // namespace

const std::vector<std::string>& preset_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& p : kPresets) v.emplace_back(p.name);
    return v;
  }();
  return names;
}

std::vector<std::string> apply_preset(const std::string& name, TrainConfig& config, const SceneInputs& scene,
                                      const cl::DeviceInfo& device) {
  const auto* p =
      std::find_if(std::begin(kPresets), std::end(kPresets), [&](const Preset& r) { return name == r.name; });
  if (p == std::end(kPresets)) throw InputError("unknown preset '" + name + "' (preview, balanced or quality)");
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
