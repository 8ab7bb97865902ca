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

// For a process whose signal handlers are its own (Python, which embeds the module): with `handle_signals`, SIGINT and
// SIGTERM ask long work to stop, as in the CLI, for the scope's length only, and the process's handlers come back
// after it. Either way the stop (a signal's or request_stop()'s) is forgotten at the scope's end, so that the next
// call starts afresh. Read stop_signal() before the scope ends.
class StopHandlerScope {
 public:
  explicit StopHandlerScope(bool handle_signals);
  ~StopHandlerScope();
  StopHandlerScope(const StopHandlerScope&) = delete;
  StopHandlerScope& operator=(const StopHandlerScope&) = delete;

 private:
  bool handle_signals_;
  struct sigaction interrupt_ {
  }, terminate_{};
};

}  // namespace clr
