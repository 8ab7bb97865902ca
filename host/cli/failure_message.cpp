#include "cli/failure_message.hpp"

#include <new>

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

}  // namespace clr::cli
