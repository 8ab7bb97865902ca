#pragma once
// SIGINT/SIGTERM (and SIGHUP, a closed terminal, SIGQUIT and SIGUSR1) ask long work to stop at its next safe point (a
// trainer writes a checkpoint) instead of killing the process mid-write; the process then exits 128 + the signal's
// number (130, 143), as a shell reports a process the signal ended, so that `train && render` does not go on. A second
// signal falls back to the default action.
#include <csignal>

namespace clr {

void install_stop_handlers();
bool stop_requested();
// Takes SIGHUP, SIGQUIT and SIGUSR1 back from a library that caught them: LLVM (loaded by PoCL to build kernels)
// catches SIGUSR1 and does nothing, and swallows one SIGQUIT. They go to the stop handlers where those are
// installed, else to their default actions. Called once the OpenCL runtime has loaded and after each kernel build.
void reclaim_signals();
// The signal that asked for the stop (0: none, or request_stop()).
int stop_signal();
void request_stop();  // what the handlers do; also for tests
// How often the process was continued after a stop (SIGSTOP, Ctrl-Z, a debugger) since the handlers were installed:
// work that times itself sees the pause inside the interval in which this count changed.
unsigned continue_count();

// For a process whose signal handlers are its own (Python, which embeds the module): SIGINT and SIGTERM ask long
// work to stop, as in the CLI, for the scope's length only; the process's handlers come back after it and the stop
// is forgotten, so that the next call starts afresh. Read stop_signal() before the scope ends.
class StopHandlerScope {
 public:
  StopHandlerScope();
  ~StopHandlerScope();
  StopHandlerScope(const StopHandlerScope&) = delete;
  StopHandlerScope& operator=(const StopHandlerScope&) = delete;

 private:
  struct sigaction interrupt_ {
  }, terminate_{};
};

}  // namespace clr
