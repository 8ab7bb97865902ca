// The JSON reader every settings and run file goes through (common/input_file.hpp) on arbitrary bytes: bad input
// must end in InputError, however deep or long — never a stack overflow or a message the size of the input. The
// strictness walk runs against the document itself and against a small settings-shaped one.
#include <cstdint>
#include <string>

#include "common/error.hpp"
#include "common/input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  static const nlohmann::json known = {
      {"samples", 4}, {"seed", 1u}, {"network", {{"width", 256}, {"adam", {{"beta1", 0.9}}}}}};
  try {
    const nlohmann::json j = clr::parse_json(text, "fuzz input");
    clr::require_known_and_kept(j, j, "fuzz input");
    clr::require_known_and_kept(j, known, "fuzz input");
  } catch (const clr::InputError& e) {
    if (std::string(e.what()).size() > 1024) __builtin_trap();  // an error line echoed its input
  }
  return 0;
}
