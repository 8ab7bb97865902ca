#include "cli/failure_message.hpp"

#include <cerrno>
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

// The options whose product sizes the buffers of each command.
std::string what_to_lower(const std::string& command) {
  if (command == "train" || command.empty())
    return "lower --batch or --samples (or the network's width or log2_table in --config)";
  if (command == "residual") return "lower --points or --samples";
  // render and guide query the model in fixed-size chunks: only the model itself can be too large.
  return "the model is too large for this device: choose another with --device";
}

}  // namespace

std::string failure_message(const std::exception& e, const std::string& command) {
  std::string line = e.what();
  if (out_of_memory(e)) line += " — out of memory: " + what_to_lower(command);
  return line;
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

std::string bounded_line(std::string_view line) {
  constexpr std::size_t kWord = 256, kKeep = 96, kLine = 4096;
  std::string out;
  for (std::size_t at = 0; at < line.size() && out.size() < kLine;) {
    const std::size_t space = line.find(' ', at);
    const std::size_t end = space == std::string_view::npos ? line.size() : space;
    const std::string_view word = line.substr(at, end - at);
    if (word.size() <= kWord)
      out += word;
    else
      out += std::string(word.substr(0, kKeep)) + "…(" + std::to_string(word.size()) + " bytes)…" +
             std::string(word.substr(word.size() - kKeep / 2));
    if (end < line.size()) out += ' ';
    at = end + 1;
  }
  if (out.size() > kLine) out = out.substr(0, kLine) + "…";
  return out;
}

}  // namespace clr::cli
