#pragma once
// Other programs the CLI calls on (python3 for a sweep's figures, ffmpeg for a walkthrough's video): run, waited
// for, never required by the work itself.
#include <filesystem>
#include <string>
#include <vector>

namespace clr {

// Runs `args` (args[0] looked up on PATH) and waits for it: true when it exited 0. `quiet` sends its output to
// /dev/null.
bool run_program(std::vector<std::string> args, bool quiet);

// `name` found on PATH as an executable file; empty when it is not there.
std::filesystem::path find_program(const std::string& name);

}  // namespace clr
