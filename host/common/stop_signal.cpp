#include "common/stop_signal.hpp"

#include <atomic>
#include <csignal>

namespace clr {
namespace {
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
std::atomic<unsigned> g_continued{0};
std::atomic<bool> g_installed{false};

extern "C" void on_continue(int) { g_continued.fetch_add(1); }

extern "C" void on_stop_signal(int sig) {
  g_signal.store(sig);
  g_stop.store(true);
  std::signal(sig, SIG_DFL);  // a second Ctrl-C kills at once
}
}  // namespace

// A stop already requested stays requested: a sweep installs the handlers once and runs one training after
// another, each installing them again, and a Ctrl-C between two trainings must stop the next one too.
void install_stop_handlers() {
  // SIGHUP (the terminal closed) ends the work as cleanly as Ctrl-C: a checkpoint, not a kill. SIGQUIT (Ctrl-\)
  // and SIGUSR1 too, rather than a core dump or a kill that loses the work since the last checkpoint.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1}) std::signal(sig, on_stop_signal);
  g_installed.store(true);
  struct sigaction continued {};
  continued.sa_handler = on_continue;
  continued.sa_flags = SA_RESTART;  // a pause must not fail a read or write with EINTR
  sigemptyset(&continued.sa_mask);
  sigaction(SIGCONT, &continued, nullptr);
}

void reclaim_signals() {
  // A stop already requested leaves the default actions: a second signal ends the process at once.
  const bool ours = g_installed.load() && !g_stop.load();
  for (const int sig : {SIGHUP, SIGQUIT, SIGUSR1}) std::signal(sig, ours ? on_stop_signal : SIG_DFL);
}

bool stop_requested() { return g_stop.load(); }
int stop_signal() { return g_signal.load(); }
unsigned continue_count() { return g_continued.load(); }
void request_stop() { g_stop.store(true); }

StopHandlerScope::StopHandlerScope(bool handle_signals) : handle_signals_(handle_signals) {
  if (!handle_signals_) return;
  struct sigaction ours {};
  ours.sa_handler = on_stop_signal;
  sigemptyset(&ours.sa_mask);
  sigaction(SIGINT, &ours, &interrupt_);
  sigaction(SIGTERM, &ours, &terminate_);
}

StopHandlerScope::~StopHandlerScope() {
  if (handle_signals_) {
    sigaction(SIGINT, &interrupt_, nullptr);
    sigaction(SIGTERM, &terminate_, nullptr);
  }
  g_stop.store(false);
  g_signal.store(0);
}

}  // namespace clr
