// The mesh readers (OBJ, PLY, Mitsuba .serialized, an sdfgrid's .vol meshed) on arbitrary bytes; the first byte
// picks the reader. Bad
// input must end in InputError; a mesh that loads must pass or fail Mesh::validate the same way.
#include <cstdint>

#include "common/error.hpp"
#include "fuzz/fuzz_input.hpp"
#include "scene/mesh.hpp"
#include "scene/sdf_grid.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int format = data[0] % 4;
  const char* names[4] = {"mesh.obj", "mesh.ply", "mesh.serialized", "grid.vol"};
  const auto path = clr::fuzz::write_input(names[format], data + 1, size - 1);
  try {
    using namespace clr::scene;
    Mesh m = format == 0   ? load_obj(path)
             : format == 1 ? load_ply(path)
             : format == 2 ? load_serialized(path, 0)
                           : mesh_sdf_grid(load_vol(path), SdfNormals::smooth, "fuzz");
    m.validate("fuzz");
  } catch (const clr::InputError&) {
  }
  return 0;
}
