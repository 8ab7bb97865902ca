#pragma once
// A distributed render's image (docs/mpi.md): rank r rendered rows y ≡ r (mod ranks) of a full-size image (the
// rest 0); rank 0 receives every rank's rows and puts them in place. Pixels are copied, never summed, so the image
// is bit for bit the one a single process renders with per-pixel streams.
#include "distributed/communicator.hpp"
#include "image/image.hpp"

namespace clr::distributed {

// On rank 0 the assembled image; on the others an empty one. `mine` unchanged for a single process.
image::Image gather_interleaved_rows(const Communicator& ranks, const image::Image& mine);

}  // namespace clr::distributed
