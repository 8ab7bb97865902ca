#include "cli/failure_message.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <new>
#include <system_error>

#include "cl/error.hpp"

namespace clr::cli {
namespace {

bool out_of_memory(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e)) return true;
  const auto* cl_error = dynamic_cast<const cl::Error*>(&e);
  if (!cl_error) return false;
  switch (cl_error->status()) {
    case CL_OUT_OF_RESOURCES:
    case CL_MEM_OBJECT_ALLOCATION_FAILURE:
    case CL_INVALID_BUFFER_SIZE:  // one buffer above the device's largest allocation (1 GiB on PoCL)
    case CL_OUT_OF_HOST_MEMORY:
      return true;
    default:
      return false;
  }
}

// The host's allocator failed (not an OpenCL runtime's: on a CPU device its buffers are host memory too, and they
// are sized by the same options as a GPU's).
bool host_memory(const std::exception& e) { return dynamic_cast<const std::bad_alloc*>(&e) != nullptr; }

// The options whose product sizes the device buffers of each command.
std::string what_to_lower_on_device(const std::string& command) {
  if (command == "train" || command.empty())
    return "lower --batch or --samples (or the network's width or log2_table in --config)";
  if (command == "residual") return "lower --points or --samples";
  if (command == "sweep") return "lower --samples (or the network's width or log2_table in --config)";
  // render and guide query the model in fixed-size chunks: only the model itself can be too large.
  return "the model is too large for this device: choose another with --device";
}

// What fills this machine's memory for each command: its images, and the scene (meshes, textures, grids) for all
// that load one. `reference` and `compare` touch no device at all.
std::string what_to_lower_on_host(const std::string& command) {
  if (command == "compare") return "the images are too large for this machine's memory";
  if (command == "devices") return "this machine is out of memory";
  const std::string scene = "the scene's meshes, textures and grids may be too large for this machine's memory";
  if (command == "reference" || command == "render" || command == "guide")
    return "lower --width × --height, or " + scene;
  if (command == "residual") return "lower --points or --samples, or " + scene;
  return "lower --batch or --samples, or " + scene;
}

}  // namespace

std::string failure_message(const std::exception& e, const std::string& command) {
  std::string line = e.what();
  if (!out_of_memory(e)) return line;
  if (host_memory(e)) return line + " — out of host memory: " + what_to_lower_on_host(command);
  return line + " — out of device memory: " + what_to_lower_on_device(command);
}

bool path_at_fault(const std::filesystem::filesystem_error& e) {
  // What the path itself causes (a name too long, a file where a folder must be, a loop of links, no permission);
  // a full disk or an I/O error is the machine's.
  switch (e.code().value()) {
    case ENAMETOOLONG:
    case ENOTDIR:
    case ELOOP:
    case ENOENT:
    case EACCES:
    case EPERM:
    case EROFS:
    case EISDIR:
    case EEXIST:
      return e.code().category() == std::generic_category() || e.code().category() == std::system_category();
    default:
      return false;
  }
}

std::string path_message(const std::filesystem::filesystem_error& e) {
  std::string line = e.path1().string();
  if (!e.path2().empty()) line += ", " + e.path2().string();
  return line + ": " + e.code().message();
}

namespace {

// Where a cut at or before `at` keeps every UTF-8 character whole (`s` is well formed: terminal_safe's output).
std::size_t character_boundary(std::string_view s, std::size_t at) {
  at = std::min(at, s.size());
  while (at > 0 && at < s.size() && (static_cast<unsigned char>(s[at]) & 0xc0) == 0x80) --at;
  return at;
}

}  // namespace

std::string bounded_line(std::string_view raw) {
  constexpr std::size_t kWord = 256, kKeep = 96, kLine = 4096;
  const std::string safe = terminal_safe(raw);
  const std::string_view line = safe;
  std::string out;
  for (std::size_t at = 0; at < line.size() && out.size() < kLine;) {
    const std::size_t space = line.find(' ', at);
    const std::size_t end = space == std::string_view::npos ? line.size() : space;
    const std::string_view word = line.substr(at, end - at);
    if (word.size() <= kWord) {
      out += word;
    } else {
      const std::size_t head = character_boundary(word, kKeep);
      const std::size_t tail = character_boundary(word, word.size() - kKeep / 2);
      out += std::string(word.substr(0, head)) + "…(" + std::to_string(word.size()) + " bytes)…" +
             std::string(word.substr(tail));
    }
    if (end < line.size()) out += ' ';
    at = end + 1;
  }
  if (out.size() > kLine) out = out.substr(0, character_boundary(out, kLine)) + "…";
  return out;
}

}  // namespace clr::cli
