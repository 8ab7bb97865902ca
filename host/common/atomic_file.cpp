#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/stop_signal.hpp"

namespace clr {
namespace fs = std::filesystem;
namespace {

// How long an output FIFO may wait for its reader to open it.
constexpr int kFifoReaderSeconds = 10;

// Runs `write` on `tmp` and hands the finished file to `place`; the temporary never outlives a failure.
void write_then(const fs::path& tmp, const std::function<void(const fs::path&)>& write,
                const std::function<void()>& place) {
  try {
    write(tmp);
    place();
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

// prefix + name + suffix, with `name` shortened where the whole would not fit a file name (NAME_MAX, 255 bytes on
// Linux): an output with a valid 254-byte name must not fail for its temporary's sake. A shortened temporary keeps
// its pid suffix, so it is still unique to this process.
std::string temporary_name(const std::string& prefix, const std::string& name, const std::string& suffix) {
  constexpr std::size_t kNameMax = 255;
  const std::size_t room = kNameMax - std::min(kNameMax, prefix.size() + suffix.size());
  return prefix + name.substr(0, room) + suffix;
}

// Copies a finished temporary into a target that must not be replaced (a device, FIFO, socket).
// Plain write(2), so that the reason of a failure (ENOSPC on a full disk, /dev/full) reaches the message.
void copy_into(const fs::path& from, const fs::path& to) {
  std::ifstream in(from, std::ios::binary);
  // Opened without blocking: a FIFO that no process reads would otherwise hold the command here forever. A reader
  // started beside the command may open its end a moment later, so one is waited for, but not for long.
  int fd = -1;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(kFifoReaderSeconds);
  while ((fd = ::open(to.c_str(), O_WRONLY | O_CLOEXEC | O_NONBLOCK)) < 0 && errno == ENXIO &&
         std::chrono::steady_clock::now() < give_up && !stop_requested())
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (fd < 0 && errno == ENXIO)
    throw InputError("output " + to.string() + " is a FIFO that no process read within " +
                     std::to_string(kFifoReaderSeconds) + " s: nothing was written");
  if (fd < 0) throw std::runtime_error("cannot open " + to.string() + " for writing: " + std::strerror(errno));
  // Written blocking from here: a reader that is slower than this process must get the whole output.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    for (std::streamsize done = 0, n = in.gcount(); done < n;) {
      const ssize_t w = ::write(fd, buffer + done, std::size_t(n - done));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        const int err = w < 0 ? errno : ENOSPC;
        ::close(fd);
        throw std::runtime_error("writing " + to.string() + " failed: " + std::strerror(err));
      }
      done += w;
    }
  }
  if (::close(fd) != 0) throw std::runtime_error("writing " + to.string() + " failed: " + std::strerror(errno));
  if (in.bad()) throw std::runtime_error("reading back the temporary for " + to.string() + " failed");
}

}  // namespace

void write_atomically(const fs::path& requested, const std::function<void(const fs::path&)>& write) {
  std::error_code ec;
  // A link's target is what the user means to overwrite; renaming onto the link itself would replace the link.
  const fs::path path =
      fs::is_symlink(requested, ec) && fs::exists(requested, ec) ? fs::canonical(requested) : requested;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) throw InputError("output " + requested.string() + " is a directory");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // The target's folder may not take new files (/dev): the temporary goes to the system's temporary folder.
    const fs::path tmp = fs::temp_directory_path() / temporary_name("clradiosity-" + std::to_string(::getpid()) + "-",
                                                                    path.filename().string(), ".tmp");
    write_then(tmp, write, [&] {
      copy_into(tmp, path);
      fs::remove(tmp);
    });
    return;
  }
  const fs::path tmp =
      path.parent_path() / temporary_name("", path.filename().string(), ".tmp" + std::to_string(::getpid()));
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  write_then(tmp, write, [&] { fs::rename(tmp, path); });
}

void require_writable_directory(const fs::path& dir, const std::string& what) {
  const fs::path probe = dir / (".clradiosity-probe" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    const int err = errno;
    const std::string line = what + " " + dir.string() + ": " + std::strerror(err);
    // A full disk or a failing device is not the user's path; everything else is (exit 2, docs/design.md §4).
    if (err == ENOSPC || err == EIO || err == EDQUOT || err == ENOMEM) throw std::runtime_error(line);
    throw InputError(line);
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

void require_output_path(const fs::path& path, const std::string& option) {
  std::error_code ec;
  // A name the file system cannot hold fails only when the finished output is renamed into place: checked here,
  // before the work, against the limits of the folder it goes into (NAME_MAX per name, PATH_MAX for the whole).
  {
    const fs::path whole = fs::absolute(path, ec);
    fs::path existing = whole.parent_path();
    while (!existing.empty() && !fs::exists(existing, ec) && existing != existing.parent_path())
      existing = existing.parent_path();
    const long name_max = ::pathconf(existing.c_str(), _PC_NAME_MAX),
               path_max = ::pathconf(existing.c_str(), _PC_PATH_MAX);
    for (const auto& part : whole)
      if (name_max > 0 && part.native().size() > std::size_t(name_max))
        throw InputError(option + ": the name '" + clip(part.string(), 48) + "' in " + clip(path.string(), 96) +
                         " is " + std::to_string(part.native().size()) + " bytes long, more than the " +
                         std::to_string(name_max) + " a file name may have");
    if (path_max > 0 && whole.native().size() >= std::size_t(path_max))
      throw InputError(option + ": the path " + clip(path.string(), 96) + " is " +
                       std::to_string(whole.native().size()) + " bytes long, more than the " +
                       std::to_string(path_max - 1) + " a path may have");
  }
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) throw InputError(option + ": output " + path.string() + " is a directory");
  // A device or FIFO is written through (write_atomically), its folder never gets a file.
  if (fs::exists(status) && !fs::is_regular_file(status)) return;
  // write_atomically creates missing folders, so the nearest one that exists must take new entries.
  fs::path dir = fs::absolute(path, ec).parent_path();
  while (!dir.empty() && !fs::exists(dir, ec) && dir != dir.parent_path()) dir = dir.parent_path();
  if (!fs::is_directory(dir, ec))
    throw InputError(option + ": cannot write " + path.string() + ": " + dir.string() + " is not a directory");
  require_writable_directory(dir, option + ": cannot write " + path.string() + " in");
}

namespace {

struct Identity {
  bool exists = false;
  bool regular = false;
  dev_t device = 0;
  ino_t inode = 0;
  fs::path path;  // where it does not exist
  bool operator==(const Identity& o) const {
    return exists == o.exists && (exists ? device == o.device && inode == o.inode : path == o.path);
  }
};

Identity identity_of(const fs::path& p) {
  Identity id;
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) {
    id.exists = true;
    id.regular = S_ISREG(st.st_mode);
    id.device = st.st_dev;
    id.inode = st.st_ino;
  } else {
    std::error_code ec;
    id.path = fs::weakly_canonical(fs::absolute(p, ec), ec);
  }
  return id;
}

}  // namespace

void require_outputs(const std::vector<Output>& outputs, const std::vector<fs::path>& inputs) {
  std::vector<std::pair<Identity, const Output*>> seen;
  for (const auto& out : outputs) {
    if (out.path.empty()) continue;
    require_output_path(out.path, out.option);
    const Identity id = identity_of(out.path);
    if (id.exists && !id.regular) continue;  // a device or FIFO: written through, replaces nothing
    for (const auto& in : inputs)
      if (!in.empty() && identity_of(in) == id)
        throw InputError(out.option + ": output " + out.path.string() + " is the input " + in.string() +
                         "; it would be overwritten");
    for (const auto& [other_id, other] : seen)
      if (other_id == id)
        throw InputError(out.option + ": output " + out.path.string() + " is also the output of " + other->option);
    seen.emplace_back(id, &out);
  }
}

void require_file_target(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw InputError(what + " " + path.string() +
                     " is not a regular file (a device, FIFO or socket): it is kept as a file, never written through "
                     "one");
}

void write_record_atomically(const fs::path& path, std::string_view text, const std::string& what) {
  require_file_target(path, what);
  write_text_atomically(path, text);
}

void write_text_atomically(const fs::path& path, std::string_view text) {
  write_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(text.data(), std::streamsize(text.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path.string());
  });
}

}  // namespace clr
