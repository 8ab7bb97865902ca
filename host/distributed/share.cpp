#include "distributed/share.hpp"

namespace clr::distributed {

Share share_of(std::size_t total, int rank, int ranks) {
  const auto r = std::size_t(rank), n = std::size_t(ranks);
  const std::size_t first = total * r / n, last = total * (r + 1) / n;
  return {first, last - first};
}

}  // namespace clr::distributed
