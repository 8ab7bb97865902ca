// The Mitsuba XML loader on arbitrary bytes: bad input must end in InputError (exit 2); anything else thrown, a
// crash, a sanitizer report, a hang or an allocation past libFuzzer's RSS limit is a finding.
#include <cstdint>

#include "common/error.hpp"
#include "fuzz/fuzz_input.hpp"
#include "scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = clr::fuzz::write_input("scene.xml", data, size);
  try {
    (void)clr::scene::load_scene(path);
  } catch (const clr::InputError&) {
  }
  return 0;
}
