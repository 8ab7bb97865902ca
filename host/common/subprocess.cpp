#include "common/subprocess.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <thread>

#include "common/stop_signal.hpp"

extern char** environ;

namespace clr {

ProgramResult run_program(std::vector<std::string> args, bool quiet) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The child's stderr goes to a file of ours: a failing tool's traceback or log is reduced to its last line.
  char err_name[] = "/tmp/clradiosity-stderr-XXXXXX";
  const int err_fd = ::mkstemp(err_name);
  if (err_fd >= 0) ::unlink(err_name);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  if (err_fd >= 0)
    posix_spawn_file_actions_adddup2(&actions, err_fd, 2);
  else
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  int status = -1;
  ProgramResult result;
  if (posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) {
    posix_spawn_file_actions_destroy(&actions);
    if (err_fd >= 0) ::close(err_fd);
    result.cause = args[0] + " could not be started";
    return result;
  }
  posix_spawn_file_actions_destroy(&actions);
  // Polled rather than blocking: the stop handlers restart an interrupted waitpid, so a blocking wait would hold a
  // Ctrl-C or SIGTERM until the child ended on its own. A stop is passed on; a child that ignores it is killed.
  auto stopped_at = std::chrono::steady_clock::time_point::max();
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid || (done < 0 && errno != EINTR)) break;
    if (stop_requested()) {
      const auto now = std::chrono::steady_clock::now();
      if (stopped_at == std::chrono::steady_clock::time_point::max()) {
        stopped_at = now;
        ::kill(pid, stop_signal() > 0 ? stop_signal() : SIGTERM);
      } else if (now - stopped_at > std::chrono::seconds(1)) {
        ::kill(pid, SIGKILL);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  result.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!result.ok) {
    std::string text;
    if (err_fd >= 0) {
      ::lseek(err_fd, 0, SEEK_SET);
      char buffer[4096];
      for (ssize_t n; (n = ::read(err_fd, buffer, sizeof buffer)) > 0;) {
        text.append(buffer, std::size_t(n));
        if (text.size() > (1u << 16)) text.erase(0, text.size() - (1u << 15));  // only the end is wanted
      }
    }
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
    const auto line_start = text.find_last_of('\n');
    result.cause = line_start == std::string::npos ? text : text.substr(line_start + 1);
    if (result.cause.empty())
      result.cause = WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status))
                     : WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                         : "ended abnormally";
  }
  if (err_fd >= 0) ::close(err_fd);
  return result;
}

std::filesystem::path find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  for (std::size_t at = 0; at <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', at), dirs.size());
    const std::filesystem::path candidate = std::filesystem::path(dirs.substr(at, end - at)) / name;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    at = end + 1;
  }
  return {};
}

}  // namespace clr
