#include "distributed/image_rows.hpp"

#include <algorithm>

namespace clr::distributed {

image::Image gather_interleaved_rows(const Communicator& ranks, const image::Image& mine) {
  if (!ranks.distributed()) return mine;
  const auto R = std::size_t(ranks.size()), H = std::size_t(mine.height), row = std::size_t(mine.width) * 3;
  std::vector<float> part;
  for (std::size_t y = std::size_t(ranks.rank()); y < H; y += R)
    part.insert(part.end(), mine.rgb.begin() + std::ptrdiff_t(y * row),
                mine.rgb.begin() + std::ptrdiff_t((y + 1) * row));
  const std::vector<float> all = ranks.gather(part);
  if (ranks.rank() != 0) return {};
  // Rank r's rows come after those of ranks 0..r-1, in increasing y.
  image::Image img(mine.width, mine.height);
  std::size_t at = 0;
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t y = r; y < H; y += R, at += row)
      std::copy_n(all.begin() + std::ptrdiff_t(at), row, img.rgb.begin() + std::ptrdiff_t(y * row));
  return img;
}

}  // namespace clr::distributed
