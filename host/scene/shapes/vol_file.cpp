// Mitsuba's grid-based volume files (.vol), the data of its `gridvolume` textures and `sdfgrid` shapes; the layout
// is described at load_vol in sdf_grid.hpp.
#include <cmath>
#include <cstring>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "scene/sdf_grid.hpp"

namespace clr::scene {

VolumeGrid load_vol(const std::filesystem::path& path) {
  const std::string what = path.string();
  const std::string file = read_input_text(path, "volume file");
  constexpr std::size_t kHeader = 48;
  if (file.size() < 4 || file.compare(0, 3, "VOL") != 0) throw InputError(what + ": not a .vol file (no 'VOL' magic)");
  if (file[3] != 3) throw InputError(what + ": unsupported .vol version " + std::to_string(int(file[3])) + " (not 3)");
  if (file.size() < kHeader) throw InputError(what + ": truncated .vol header");
  const auto int_at = [&](std::size_t at) {
    std::int32_t v;
    std::memcpy(&v, file.data() + at, sizeof v);
    return v;
  };
  const std::int32_t encoding = int_at(4);
  if (encoding != 1)
    throw InputError(what + ": unsupported .vol encoding " + std::to_string(encoding) + " (only 1, float32, is read)");
  VolumeGrid g;
  for (int a = 0; a < 3; ++a) {
    g.size[a] = int_at(8 + 4 * std::size_t(a));
    if (g.size[a] < 2 || g.size[a] > kMaxVolumeResolution)
      throw InputError(what + ": resolution " + std::to_string(g.size[a]) + " along " + "xyz"[a] + " is outside [2, " +
                       std::to_string(kMaxVolumeResolution) + "]");
  }
  g.channels = int_at(20);
  if (g.channels < 1 || g.channels > 4)
    throw InputError(what + ": " + std::to_string(g.channels) + " channels (a .vol holds 1 to 4)");
  const std::size_t count =
      std::size_t(g.size.x) * std::size_t(g.size.y) * std::size_t(g.size.z) * std::size_t(g.channels);
  if (file.size() - kHeader < 4 * count)
    throw InputError(what + ": the header announces " + std::to_string(count) + " values, more than the file's " +
                     std::to_string(file.size() - kHeader) + " bytes of data hold");
  g.values.resize(count);
  std::memcpy(g.values.data(), file.data() + kHeader, 4 * count);
  for (std::size_t i = 0; i < count; ++i)
    if (!std::isfinite(g.values[i])) throw InputError(what + ": value " + std::to_string(i) + " is not finite");
  return g;
}

}  // namespace clr::scene
