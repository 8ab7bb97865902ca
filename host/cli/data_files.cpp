#include "cli/data_files.hpp"

#include <system_error>

namespace clr::cli {
namespace fs = std::filesystem;

namespace {

// share/clradiosity of the prefix this binary is installed in, or empty when it is not installed. /proc/self/exe
// names the binary itself, whatever folder it was started from and through whatever link.
fs::path installed_data_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path data = (exe.parent_path() / CLR_INSTALL_DATA_RELATIVE).lexically_normal();
  return fs::is_directory(data, ec) ? data : fs::path();
}

}  // namespace

fs::path bundled_scenes_dir() {
  const fs::path installed = installed_data_dir();
  return installed.empty() ? fs::path(CLR_SOURCE_SCENES_DIR) : installed / "scenes";
}

fs::path plot_sweep_script() {
  const fs::path installed = installed_data_dir();
  return installed.empty() ? fs::path(CLR_SOURCE_PLOT_SCRIPT) : installed / "plot_sweep.py";
}

}  // namespace clr::cli
