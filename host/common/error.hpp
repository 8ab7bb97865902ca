#pragma once
// Two kinds of failure, mapped to the CLI's exit codes (docs/design.md §4):
//   InputError   - bad input or usage (a file, element, value or option at fault): exit 2.
//   other std::exception - a runtime failure (device ran out of memory, I/O error mid-run): exit 1.
// Messages are one line that names the culprit, so a user can act on it without a stack trace.
#include <stdexcept>
#include <string>

namespace clr {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace clr
