#include "common/stop_signal.hpp"

#include <atomic>
#include <csignal>

namespace clr {
namespace {
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
std::atomic<unsigned> g_continued{0};
std::atomic<bool> g_installed{false};
// What each signal did before our handler went in: a signal that was ignored (nohup, `trap '' INT`, SIG_IGN) stays
// ignored, a handler that was there (a host program's) is called after ours, and a second signal gets it back.
struct sigaction g_before[NSIG];
bool g_known[NSIG];  // g_before[sig] holds what was there

extern "C" void on_continue(int) { g_continued.fetch_add(1); }

extern "C" void on_stop_signal(int sig, siginfo_t* info, void* context) {
  g_signal.store(sig);
  g_stop.store(true);
  // A second signal meets what was there before: the default action (a second Ctrl-C kills at once) or the host's.
  const struct sigaction& before = g_before[sig];
  sigaction(sig, &before, nullptr);
  if (before.sa_flags & SA_SIGINFO) {
    if (before.sa_sigaction) before.sa_sigaction(sig, info, context);
  } else if (before.sa_handler != SIG_DFL && before.sa_handler != SIG_IGN) {
    before.sa_handler(sig);
  }
}

bool is_ours(const struct sigaction& a) { return (a.sa_flags & SA_SIGINFO) && a.sa_sigaction == on_stop_signal; }

// Puts the stop handler on `sig`, unless what was there ignores it. `look_again`: take what is there now as what was
// there before (a caller's scope: Python's handlers); otherwise keep what was first seen (the CLI's start, before a
// library — LLVM, under PoCL — put handlers of its own that end the process, which must not be chained to).
void take(int sig, bool look_again) {
  struct sigaction now {};
  sigaction(sig, nullptr, &now);
  if (!is_ours(now) && (look_again || !g_known[sig])) {
    g_before[sig] = now;
    g_known[sig] = true;
  }
  if (g_before[sig].sa_handler == SIG_IGN && !(g_before[sig].sa_flags & SA_SIGINFO)) {
    sigaction(sig, &g_before[sig], nullptr);
    return;
  }
  struct sigaction ours {};
  ours.sa_sigaction = on_stop_signal;
  ours.sa_flags = SA_SIGINFO;
  sigemptyset(&ours.sa_mask);
  sigaction(sig, &ours, nullptr);
}
}  // namespace

// A stop already requested stays requested: a sweep installs the handlers once and runs one training after
// another, each installing them again, and a Ctrl-C between two trainings must stop the next one too.
void install_stop_handlers() {
  // SIGHUP (the terminal closed) ends the work as cleanly as Ctrl-C: a checkpoint, not a kill. SIGQUIT (Ctrl-\)
  // and SIGUSR1 too, rather than a core dump or a kill that loses the work since the last checkpoint.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1}) take(sig, false);
  g_installed.store(true);
  struct sigaction continued {};
  continued.sa_handler = on_continue;
  continued.sa_flags = SA_RESTART;  // a pause must not fail a read or write with EINTR
  sigemptyset(&continued.sa_mask);
  sigaction(SIGCONT, &continued, nullptr);
}

void remember_signal_dispositions() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1})
    if (!g_known[sig]) {
      sigaction(sig, nullptr, &g_before[sig]);
      g_known[sig] = true;
    }
}

void reclaim_signals() {
  // A stop already requested leaves what was there before: a second signal meets it.
  const bool ours = g_installed.load() && !g_stop.load();
  for (const int sig : {SIGHUP, SIGQUIT, SIGUSR1}) {
    if (ours) {
      take(sig, false);
    } else if (g_known[sig]) {
      sigaction(sig, &g_before[sig], nullptr);
    } else {
      std::signal(sig, SIG_DFL);
    }
  }
}

bool stop_requested() { return g_stop.load(); }
int stop_signal() { return g_signal.load(); }
unsigned continue_count() { return g_continued.load(); }
void request_stop() { g_stop.store(true); }

StopHandlerScope::StopHandlerScope(bool handle_signals) : handle_signals_(handle_signals) {
  if (!handle_signals_) return;
  sigaction(SIGINT, nullptr, &interrupt_);
  sigaction(SIGTERM, nullptr, &terminate_);
  take(SIGINT, true);
  take(SIGTERM, true);
}

bool StopHandlerScope::host_handles(int sig) const {
  const struct sigaction& a = sig == SIGINT ? interrupt_ : terminate_;
  if (!handle_signals_ || (sig != SIGINT && sig != SIGTERM)) return false;
  return (a.sa_flags & SA_SIGINFO) ? a.sa_sigaction != nullptr : a.sa_handler != SIG_DFL && a.sa_handler != SIG_IGN;
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
