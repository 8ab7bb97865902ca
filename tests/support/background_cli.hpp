#pragma once
// A CLI command started in the background, for the tests of signals, locks and concurrent runs: its output
// discarded, the test waiting on a file it writes (a log's rows, frames) before it signals or checks it.
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/cli_run_dir.hpp"

namespace clr::test {

// Starts `binary` (argv[0] "clradiosity") with `args`, its stdout and stderr to /dev/null, in `cwd` when one is
// given; returns its pid (negative when fork failed). The argument vector is built before fork: the child only
// redirects and execs.
inline pid_t spawn_cli(const std::vector<std::string>& args, const std::filesystem::path& cwd = {},
                       const std::string& binary = CLR_CLI_PATH) {
  std::vector<std::string> words = {"clradiosity"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(126);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

// A command line's words, split at spaces (no quoting: test paths have no spaces).
inline std::vector<std::string> words(const std::string& command_line) {
  std::vector<std::string> out;
  std::istringstream split(command_line);
  for (std::string w; split >> w;) out.push_back(w);
  return out;
}

// Waits up to `seconds` until the file at `p` has at least `n` lines (a log's rows); whether it has.
inline bool wait_for_lines(const std::filesystem::path& p, std::size_t n, int seconds = 120) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (lines_in(p) < n && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return lines_in(p) >= n;
}

}  // namespace clr::test
