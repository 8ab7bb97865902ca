#include "support/run_cli.hpp"

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace clr::test {
namespace {
std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

CliResult run_cli(const std::string& args, const std::string& env) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("clr_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto out = dir / "out.txt", err = dir / "err.txt";
  const std::string cmd = (env.empty() ? "" : "env " + env + " ") + "'" + CLR_CLI_PATH + "' " + args + " >'" +
                          out.string() + "' 2>'" + err.string() + "' </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r{WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), slurp(out), slurp(err)};
  fs::remove_all(dir);
  return r;
}

}  // namespace clr::test
