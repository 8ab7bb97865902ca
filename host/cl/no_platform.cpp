#include "cl/no_platform.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/atomic_file.hpp"

namespace clr::cl {
namespace fs = std::filesystem;
namespace {

// PoCL's cache folder, as PoCL chooses it.
fs::path pocl_cache_folder() {
  if (const char* dir = std::getenv("POCL_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "pocl";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "pocl";
  return {};
}

// "" when PoCL could make and write its cache folder; else why not.
std::string pocl_cache_problem() {
  const fs::path dir = pocl_cache_folder();
  if (dir.empty()) return "neither POCL_CACHE_DIR, XDG_CACHE_HOME nor HOME is set";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return "folder " + dir.string() + ": " + ec.message();
  try {
    require_writable_directory(dir, "folder");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

std::string no_platform_cause() {
  const char* env = std::getenv("OCL_ICD_VENDORS");
  const fs::path vendors = env && *env ? fs::path(env) : fs::path("/etc/OpenCL/vendors");
  const std::string where = env && *env ? "OCL_ICD_VENDORS=" + vendors.string() : vendors.string();
  std::vector<fs::path> icds;
  std::error_code ec;
  if (fs::is_regular_file(vendors, ec))
    icds.push_back(vendors);
  else if (fs::is_directory(vendors, ec))
    for (const auto& e : fs::directory_iterator(vendors, ec))
      if (e.path().extension() == ".icd") icds.push_back(e.path());
  if (icds.empty())
    return "no OpenCL platform: " + where + " registers no driver (no .icd file" +
           (fs::exists(vendors, ec) ? "" : std::string(": it does not exist")) +
           "); install pocl-opencl-icd or a GPU driver";
  bool pocl = false;
  std::string names;
  for (const auto& icd : icds) {
    std::ifstream in(icd);
    std::stringstream text;
    text << in.rdbuf();
    pocl = pocl || text.str().find("pocl") != std::string::npos;
    names += (names.empty() ? "" : ", ") + icd.filename().string();
  }
  if (pocl)
    if (const std::string problem = pocl_cache_problem(); !problem.empty())
      return "no OpenCL platform: PoCL's kernel cache folder is not usable (" + problem +
             ") and PoCL then registers no platform; point POCL_CACHE_DIR (or XDG_CACHE_HOME) at a writable folder";
  return "no OpenCL platform: the drivers registered in " + where + " (" + names +
         ") started none (a driver library missing or failing; OCL_ICD_DEBUG=7 shows the loader's steps)";
}

std::string pocl_cache_cause(const std::string& platform_name) {
  if (platform_name.find("Portable Computing Language") == std::string::npos) return "";
  if (const char* off = std::getenv("POCL_KERNEL_CACHE"); off && std::string(off) == "0") return "";
  const std::string problem = pocl_cache_problem();
  if (problem.empty()) return "";
  return "PoCL's kernel cache folder is not usable (" + problem +
         "): PoCL cannot build kernels; point POCL_CACHE_DIR (or XDG_CACHE_HOME) at a writable folder";
}

}  // namespace clr::cl
