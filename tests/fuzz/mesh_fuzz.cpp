// The mesh readers (OBJ, PLY, Mitsuba .serialized) on arbitrary bytes; the first byte picks the reader. Bad
// input must end in InputError; a mesh that loads must pass or fail Mesh::validate the same way.
#include <cstdint>

#include "common/error.hpp"
#include "fuzz/fuzz_input.hpp"
#include "scene/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int format = data[0] % 3;
  const char* names[3] = {"mesh.obj", "mesh.ply", "mesh.serialized"};
  const auto path = clr::fuzz::write_input(names[format], data + 1, size - 1);
  try {
    clr::scene::Mesh m = format == 0   ? clr::scene::load_obj(path)
                         : format == 1 ? clr::scene::load_ply(path)
                                       : clr::scene::load_serialized(path, 0);
    m.validate("fuzz");
  } catch (const clr::InputError&) {
  }
  return 0;
}
