#include "cli/data_files.hpp"

#include <system_error>

#include "common/error.hpp"

namespace clr::cli {
namespace fs = std::filesystem;

namespace {

// This binary itself, whatever folder it was started from and through whatever link.
fs::path executable() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe;
}

// share/clradiosity of the prefix this binary is installed in, or empty when it is not installed.
fs::path installed_data_dir() {
  const fs::path exe = executable();
  if (exe.empty()) return {};
  std::error_code ec;
  const fs::path data = (exe.parent_path() / CLR_INSTALL_DATA_RELATIVE).lexically_normal();
  return fs::is_directory(data, ec) ? data : fs::path();
}

// Whether this is the binary where the build wrote it, whose data is the source tree's.
bool in_build_tree() {
  std::error_code ec;
  const fs::path exe = executable();
  return !exe.empty() && fs::equivalent(exe, CLR_BUILD_BINARY, ec);
}

}  // namespace

fs::path bundled_scenes_dir() {
  if (const fs::path installed = installed_data_dir(); !installed.empty()) return installed / "scenes";
  if (in_build_tree()) return CLR_SOURCE_SCENES_DIR;
  const fs::path exe = executable();
  throw InputError("the bundled scenes are not beside this binary (looked for " +
                   (exe.parent_path() / CLR_INSTALL_DATA_RELATIVE).lexically_normal().string() +
                   "/scenes): install it with `cmake --install BUILD_DIR --prefix PREFIX`, or copy share/clradiosity "
                   "with it");
}

fs::path plot_sweep_script() {
  if (const fs::path installed = installed_data_dir(); !installed.empty()) return installed / "plot_sweep.py";
  return in_build_tree() ? fs::path(CLR_SOURCE_PLOT_SCRIPT) : fs::path();
}

}  // namespace clr::cli
