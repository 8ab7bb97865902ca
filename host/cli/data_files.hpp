#pragma once
// Where the binary finds the files it reads at run time besides its inputs: the bundled scenes (the main job's
// Cornell box) and the sweep's figure script. An installed binary (`cmake --install`, GNU layout) finds them
// relative to itself — bin/clradiosity → share/clradiosity/{scenes, plot_sweep.py} — so a prefix can be moved or
// copied and the binary run from any folder; the binary where the build wrote it reads them from the source tree it
// was built from. A binary copied elsewhere without share/ beside it has neither: it says so, rather than read the
// build machine's source tree as if it were its own.
#include <filesystem>

namespace clr::cli {

// InputError naming where the scenes were looked for, for a binary copied without its data.
std::filesystem::path bundled_scenes_dir();
// Empty for a binary copied without its data (a sweep then draws no figures, and says why).
std::filesystem::path plot_sweep_script();

}  // namespace clr::cli
