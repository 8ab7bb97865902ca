#include "common/address_space.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <fstream>

namespace clr {
namespace {

// What a runtime needs beside the buffers it is asked for (kernel builds, queues, its threads' stacks).
constexpr std::uint64_t kRuntimeMargin = std::uint64_t(256) << 20;

std::string mib(std::uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

}  // namespace

std::optional<std::uint64_t> address_space_left() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return std::nullopt;
  // /proc/self/statm's first field: the pages mapped now.
  std::uint64_t pages = 0;
  std::ifstream("/proc/self/statm") >> pages;
  const std::uint64_t mapped = pages * std::uint64_t(::sysconf(_SC_PAGESIZE));
  return mapped < limit.rlim_cur ? std::uint64_t(limit.rlim_cur) - mapped : 0;
}

void require_address_space(std::uint64_t bytes, std::uint64_t reserved, const std::string& what) {
  const auto left = address_space_left();
  if (!left || bytes + reserved + kRuntimeMargin <= *left) return;
  throw AddressSpaceExhausted(what + " of " + mib(bytes) + " does not fit under the address-space limit (ulimit -v): " +
                              mib(*left) + " left, " + mib(reserved) + " of it promised to earlier buffers, " +
                              mib(kRuntimeMargin) + " kept for the OpenCL runtime");
}

}  // namespace clr
