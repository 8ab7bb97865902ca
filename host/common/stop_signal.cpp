#include "common/stop_signal.hpp"

#include <atomic>
#include <csignal>

namespace clr {
namespace {
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};

extern "C" void on_stop_signal(int sig) {
  g_signal.store(sig);
  g_stop.store(true);
  std::signal(sig, SIG_DFL);  // a second Ctrl-C kills at once
}
}  // namespace

// A stop already requested stays requested: a sweep installs the handlers once and runs one training after
// another, each installing them again, and a Ctrl-C between two trainings must stop the next one too.
void install_stop_handlers() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

bool stop_requested() { return g_stop.load(); }
int stop_signal() { return g_signal.load(); }
void request_stop() { g_stop.store(true); }

}  // namespace clr
