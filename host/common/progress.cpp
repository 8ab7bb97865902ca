#include "common/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace clr {
namespace {
std::string duration_text(double s) {
  char buf[32];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, int(s) / 60 % 60);
  return buf;
}
}  // namespace

double eta_seconds(double elapsed, double done, double already_done, double total) {
  const double here = done - already_done;
  return here > 0 ? elapsed * (total - done) / here : 0.0;
}

Progress::Progress(std::string label, double total, double interval_seconds, double already_done)
    : label_(std::move(label)),
      total_(total),
      interval_(interval_seconds),
      already_done_(already_done),
      tty_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

Progress::~Progress() {
  if (tty_ && !finished_ && !silent_) std::fputc('\n', stderr);
}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::update(double done, const std::string& detail) {
  // Threads that finish work report in whatever order they reach the reporter: a report behind one already made is
  // stale (the final line once read 25 % of a render that had finished).
  if (done < last_done_) return;
  last_done_ = done;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (since < (tty_ ? 0.2 : interval_)) return;
  last_print_ = now;
  print(done, detail, false);
}

void Progress::finish(const std::string& detail) {
  print(last_done_, detail, true);
  finished_ = true;
}

void Progress::silence_process() { silent_ = true; }

void Progress::print(double done, const std::string& detail, bool final) {
  if (silent_) return;
  const double t = elapsed_seconds();
  std::string line = label_;
  char buf[96];
  if (total_ > 0) {
    std::snprintf(buf, sizeof buf, " %5.1f%%", 100.0 * done / total_);
    line += buf;
  }
  line += " " + duration_text(t);
  if (total_ > 0 && done > already_done_ && !final)
    line += " (ETA " + duration_text(eta_seconds(t, done, already_done_, total_)) + ")";
  if (!detail.empty()) line += "  " + detail;
  if (tty_)
    std::fprintf(stderr, "\r\033[K%s%s", line.c_str(), final ? "\n" : "");
  else
    std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

}  // namespace clr
