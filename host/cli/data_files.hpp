#pragma once
// Where the binary finds the files it reads at run time besides its inputs: the bundled scenes (the main job's
// Cornell box) and the sweep's figure script. An installed binary (`cmake --install`, GNU layout) finds them
// relative to itself — bin/clradiosity → share/clradiosity/{scenes, plot_sweep.py} — so a prefix can be moved or
// copied and the binary run from any folder; a binary in the build tree, which has no share/ beside it, reads them
// from the source tree it was built from.
#include <filesystem>

namespace clr::cli {

std::filesystem::path bundled_scenes_dir();
std::filesystem::path plot_sweep_script();

}  // namespace clr::cli
