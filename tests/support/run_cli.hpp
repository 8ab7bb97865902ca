#pragma once
// Runs the built clradiosity binary and captures its exit code, stdout and stderr.
#include <string>

namespace clr::test {

struct CliResult {
  int exit_code;
  std::string out;
  std::string err;
};

// `args` is appended to the binary's path as shell words; `env` (e.g. "CLRADIOSITY_DEVICE=x") is prefixed.
CliResult run_cli(const std::string& args, const std::string& env = "");

}  // namespace clr::test
