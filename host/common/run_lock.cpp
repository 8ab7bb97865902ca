#include "common/run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace clr {

RunLock::RunLock(const std::filesystem::path& dir, bool create) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
    throw InputError("run directory " + dir.string() + " exists and is not a directory");
  if (!create && !std::filesystem::exists(dir, ec))
    throw InputError("run directory " + dir.string() + " does not exist (no checkpoint to resume)");
  // The run directory is the user's -o: a path through a file (/etc/hostname/x), a read-only or pseudo file
  // system are theirs to fix (exit 2), and it is better found before the networks are built than at the first
  // checkpoint.
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    const bool system_fault = ec == std::errc::no_space_on_device || ec == std::errc::io_error;
    const std::string line = "run directory " + dir.string() + " cannot be created: " + ec.message();
    if (system_fault) throw std::runtime_error(line);
    throw InputError(line);
  }
  require_writable_directory(dir, "run directory");
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot open run directory " + dir.string() + ": " + std::strerror(errno));
  // Non-blocking: waiting for another run to finish could take hours; the user should choose instead.
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd_);
    if (err == EWOULDBLOCK)
      throw InputError("run directory " + dir.string() +
                       " is in use by another training; wait for it to end or choose another -o");
    throw std::runtime_error("cannot lock run directory " + dir.string() + ": " + std::strerror(err));
  }
}

RunLock::~RunLock() { ::close(fd_); }  // closing the descriptor releases the lock

}  // namespace clr
