// `cmake --install`: the installed binary finds its data (the bundled scenes, the sweep's figure script) relative
// to itself, so a prefix runs from any folder, moved or copied, with nothing read from the source tree.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/background_cli.hpp"
#include "support/cli_run_dir.hpp"
#include "support/test_python.hpp"

namespace clr::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class InstallCli : public CliRunDir {
 protected:
  InstallCli() : CliRunDir("install_cli") {}
};

// `binary ARGS` run in `cwd`; its exit code, stderr in `err`.
int run_in(const fs::path& cwd, const fs::path& binary, const std::string& args, std::string* err = nullptr) {
  const fs::path err_file = cwd / "stderr.txt";
  const std::string cmd = "cd '" + cwd.string() + "' && '" + binary.string() + "' " + args + " >/dev/null 2>'" +
                          err_file.string() + "' </dev/null";
  const int status = std::system(cmd.c_str());
  if (err) {
    std::ifstream in(err_file);
    err->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST_F(InstallCli, AMovedPrefixRunsFromAnyFolder) {
  const fs::path prefix = dir / "prefix", moved = dir / "moved", elsewhere = dir / "elsewhere";
  const std::string install = "'" CLR_CMAKE_COMMAND "' --install '" CLR_BINARY_DIR "' --prefix '" + prefix.string() +
                              "' >'" + (dir / "install.log").string() + "' 2>&1";
  ASSERT_EQ(std::system(install.c_str()), 0) << "cmake --install failed; see " << (dir / "install.log");
  for (const char* file : {"bin/clradiosity", "share/clradiosity/scenes/cornell-box.xml",
                           "share/clradiosity/scenes/meshes/sphere-cap.obj", "share/clradiosity/plot_sweep.py"})
    EXPECT_TRUE(fs::exists(prefix / file)) << file << " is not installed";
  // Moved after installing: only a lookup relative to the binary can find the data now.
  fs::rename(prefix, moved);
  fs::create_directories(elsewhere);
  const fs::path binary = moved / "bin" / "clradiosity";

  std::string err;
  EXPECT_EQ(run_in(elsewhere, binary, "--help", &err), 0) << err;

  // The Python module, in the GNU layout's site-packages, imports from the moved prefix and loads the installed scene.
  fs::path site_packages;
  for (const auto& lib : fs::directory_iterator(moved / CLR_INSTALL_LIBDIR))
    if (lib.path().filename().string().starts_with("python")) site_packages = lib.path() / "site-packages";
  ASSERT_TRUE(fs::exists(site_packages / "clradiosity" / "__init__.py")) << "the Python module is not installed";
  if (const std::string py = test_python(); !py.empty()) {
    const std::string check = "import clradiosity as cr; assert cr.__file__.startswith('" + moved.string() +
                              "'), cr.__file__; print(cr.load_scene('" +
                              (moved / "share/clradiosity/scenes/cornell-box.xml").string() + "').film)";
    const std::string cmd = "cd '" + elsewhere.string() + "' && PYTHONPATH='" + site_packages.string() + "' '" + py +
                            "' -c \"" + check + "\" >'" + (dir / "python.out").string() + "' 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << "see " << (dir / "python.out");
  }

  // The main job trains the installed Cornell box (the run's scene record names the scene it read); SIGTERM stops
  // it cleanly once it has logged, as the main job's own test does.
  const pid_t pid = spawn_cli({}, elsewhere, binary.string());
  ASSERT_GE(pid, 0);
  const fs::path run = elsewhere / "clradiosity-out" / "cornell-box-run";
  wait_for_lines(run / "log.csv", 2);
  EXPECT_GE(lines_in(run / "log.csv"), 2u) << "the installed main job did not start training";
  ::kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143);
  const auto scene = nlohmann::json::parse(std::ifstream(run / "scene.json"));
  EXPECT_EQ(fs::path(scene.at("scene").get<std::string>()), moved / "share/clradiosity/scenes/cornell-box.xml");

  // Nothing falls back to the source tree: without the installed scene the job fails naming the installed path.
  fs::remove(moved / "share/clradiosity/scenes/cornell-box.xml");
  fs::remove_all(elsewhere / "clradiosity-out");
  EXPECT_EQ(run_in(elsewhere, binary, "", &err), 2) << err;
  EXPECT_THAT(err, HasSubstr((moved / "share/clradiosity/scenes/cornell-box.xml").string()));
}

// A binary copied elsewhere without share/ beside it has no bundled data: the main job says where it looked,
// rather than train the build machine's source-tree scene as if it were its own; a sweep draws no figures and says so.
TEST_F(InstallCli, ABinaryCopiedWithoutItsDataSaysSo) {
  const fs::path bare = dir / "bare" / "bin", elsewhere = dir / "elsewhere";
  fs::create_directories(bare);
  fs::create_directories(elsewhere);
  fs::copy_file(CLR_CLI_PATH, bare / "clradiosity");
  fs::permissions(bare / "clradiosity", fs::perms::owner_all, fs::perm_options::add);
  std::string err;
  EXPECT_EQ(run_in(elsewhere, bare / "clradiosity", "", &err), 2) << err;
  EXPECT_THAT(err, HasSubstr("the bundled scenes are not beside this binary"));
  EXPECT_THAT(err, HasSubstr((dir / "bare" / "share" / "clradiosity" / "scenes").string()));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_FALSE(fs::exists(elsewhere / "clradiosity-out")) << "refused before any output";
  // The binary where the build wrote it still reads the source tree's scenes (every CLI test relies on it).
  EXPECT_EQ(run_in(elsewhere, CLR_CLI_PATH, "--version", &err), 0) << err;
}

}  // namespace
}  // namespace clr::test
