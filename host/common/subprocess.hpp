#pragma once
// Other programs the CLI calls on (python3 for a sweep's figures, ffmpeg for a walkthrough's video): run, waited
// for, never required by the work itself.
#include <filesystem>
#include <string>
#include <vector>

namespace clr {

struct ProgramResult {
  bool ok = false;  // exited 0
  // Why not, in one line: the last line the program wrote on stderr (a traceback's last line is its error), or how
  // it ended ("not found", "killed by signal 9", "exit status 3"). Empty when ok.
  std::string cause;
};

// Runs `args` (args[0] looked up on PATH) and waits for it. Its stderr is kept, not shown (a failure becomes one
// line, ProgramResult::cause); `quiet` sends its stdout to /dev/null too. A stop requested while it runs
// (common/stop_signal.hpp) is passed on to it, and it is killed if it has not ended a second later.
ProgramResult run_program(std::vector<std::string> args, bool quiet);

// `name` found on PATH as an executable file; empty when it is not there.
std::filesystem::path find_program(const std::string& name);

}  // namespace clr
