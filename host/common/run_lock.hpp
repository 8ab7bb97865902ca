#pragma once
// One writer per run directory. Two trainings on the same RUN_DIR would interleave log.csv rows and overwrite each
// other's checkpoints; the second one is refused instead, while the first keeps running.
//
// The lock is an flock(2) on the directory itself rather than on a lock file inside it: a fresh run requires an
// empty RUN_DIR, and nothing is left behind to go stale. The kernel drops the lock when the process ends, however
// it ends (a crash or SIGKILL included), so a dead run never blocks the next.
#include <filesystem>

namespace clr {

class RunLock {
 public:
  // Locks `dir`, creating it if `create` (a fresh run) and refusing a missing one otherwise (a resumed run: an
  // empty directory left behind would only mislead). InputError naming the directory when another process
  // holds it.
  explicit RunLock(const std::filesystem::path& dir, bool create = true);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace clr
