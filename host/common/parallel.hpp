#pragma once
// A blocking parallel loop over [0, n) in chunks, on all hardware threads. Chunks are claimed dynamically so uneven
// work (a path tracer's rows, rays that miss) balances; callers derive randomness from the index, never from the
// thread, which keeps results deterministic.
#include <cstddef>
#include <functional>

namespace clr {

std::size_t worker_count();
// Calls body(begin, end) for consecutive chunks of at most `chunk` indices; rethrows the first exception.
void parallel_for(std::size_t n, std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& body);

}  // namespace clr
