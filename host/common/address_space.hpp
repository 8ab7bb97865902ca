#pragma once
// The room left under the process's address-space limit (`ulimit -v`, RLIMIT_AS). A CPU OpenCL device's buffers
// are this process's memory, and PoCL backs them only when first used — where an allocation that fails is an
// assertion (exit 134), not an error the engine could report. So buffers on a CPU device are weighed against this
// room before they are made, and refused with the out-of-memory line when they would not fit.
#include <cstdint>
#include <new>
#include <optional>
#include <string>

namespace clr {

// Bytes the process may still map; nullopt when its address space is unlimited.
std::optional<std::uint64_t> address_space_left();

// What an allocation refused for want of address space throws: a host memory failure (std::bad_alloc), with a
// message that names the limit.
class AddressSpaceExhausted : public std::bad_alloc {
 public:
  explicit AddressSpaceExhausted(std::string what) : what_(std::move(what)) {}
  const char* what() const noexcept override { return what_.c_str(); }

 private:
  std::string what_;
};

// Throws AddressSpaceExhausted naming `what` unless `bytes` (plus `reserved`, bytes promised but perhaps not yet
// mapped) fit in address_space_left() with a margin for the runtime's own needs.
void require_address_space(std::uint64_t bytes, std::uint64_t reserved, const std::string& what);

}  // namespace clr
