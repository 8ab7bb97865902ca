#pragma once
// How R ranks split M items (a step's training points, an image's rows) so that together they are the one-process
// job: rank r takes [first, first + count), the shares in rank order covering [0, M) with sizes differing by at
// most one. Streams keyed by the global index then give the union of the ranks' samples the one-process batch.
#include <cstddef>

namespace clr::distributed {

struct Share {
  std::size_t first = 0, count = 0;
};

Share share_of(std::size_t total, int rank, int ranks);

}  // namespace clr::distributed
