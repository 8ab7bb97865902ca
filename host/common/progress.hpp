#pragma once
// Progress of long work (docs/design.md §4): on a TTY one line redrawn in place; otherwise (logs, CI) a plain line at
// most every `interval` seconds, so redirected output stays readable and bounded.
#include <chrono>
#include <string>

namespace clr {

// Seconds left for `total` at the rate of this process: `done` after `elapsed` seconds, `already_done` of it from
// before (0 while nothing is done yet).
double eta_seconds(double elapsed, double done, double already_done, double total);

class Progress {
 public:
  // `label` prefixes every line ("train", "reference"); `total` is the amount of work (0: unknown), of which
  // `already_done` was done before this process (a resumed run): the ETA takes the rate of this process alone.
  Progress(std::string label, double total, double interval_seconds = 5.0, double already_done = 0);
  ~Progress();
  // Reports `done` units; `detail` is appended ("loss 0.12"). Prints only when due; a report below an earlier one
  // (another thread's, arriving late) is ignored, so the lines and the final one never go backwards.
  void update(double done, const std::string& detail = "");
  // Prints the final line unconditionally.
  void finish(const std::string& detail = "");
  double elapsed_seconds() const;
  // Silences every Progress of this process: MPI ranks other than 0, whose lines would repeat rank 0's.
  // And `-q/--quiet`: the commands' informational lines on stderr ask silenced() too (results and errors stay).
  static void silence_process();
  static bool silenced() { return silent_; }

 private:
  void print(double done, const std::string& detail, bool final);

  std::string label_;
  double total_;
  double interval_;
  double already_done_;
  bool tty_;
  bool finished_ = false;
  double last_done_ = 0;
  std::chrono::steady_clock::time_point start_, last_print_;
  static inline bool silent_ = false;
};

}  // namespace clr
