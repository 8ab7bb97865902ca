#pragma once
// SIGINT/SIGTERM (and SIGHUP, a closed terminal, SIGQUIT and SIGUSR1) ask long work to stop at its next safe point (a
// trainer writes a checkpoint) instead of killing the process mid-write; the process then exits 128 + the signal's
// number (130, 143), as a shell reports a process the signal ended, so that `train && render` does not go on. A second
// signal falls back to what was there before (the default action). A signal the process was started with ignored
// (`nohup`, `trap '' INT`) stays ignored.
#include <csignal>

namespace clr {

// Records the dispositions the process was started with (ignored or default: handlers do not survive exec), before
// any library installs its own; install_stop_handlers keeps an ignored signal ignored and gives a second signal the
// default action. A program that does not call it (the Python module's host) has its dispositions recorded where
// the handlers first go in.
void remember_signal_dispositions();
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
// after it. A signal the process ignores stays ignored; a handler of its own is called after ours (host_handles).
// Either way the stop (a signal's or request_stop()'s) is forgotten at the scope's end, so that the next call
// starts afresh. Read stop_signal() before the scope ends.
class StopHandlerScope {
 public:
  explicit StopHandlerScope(bool handle_signals);
  ~StopHandlerScope();
  StopHandlerScope(const StopHandlerScope&) = delete;
  StopHandlerScope& operator=(const StopHandlerScope&) = delete;
  // Whether the process had a handler of its own for SIGINT or SIGTERM, which then saw the signal too.
  bool host_handles(int sig) const;

 private:
  bool handle_signals_;
  struct sigaction interrupt_ {
  }, terminate_{};
};

}  // namespace clr
