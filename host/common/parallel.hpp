#pragma once
// Parallel loops on oneTBB's persistent worker pool (docs/design.md §6): a training step calls several of these, so
// threads are created once per process, not once per loop. Chunks are claimed dynamically so uneven work (a path
// tracer's rows, rays that miss) balances; callers derive randomness from the index, never from the thread, which
// keeps results the same whatever the thread count.
#include <cstddef>
#include <functional>

namespace clr {

// Caps the threads of every host stage (these loops, and Embree's, which share the pool) and, when called before the
// first OpenCL call, PoCL's CPU device too (`--threads N`, CLRADIOSITY_THREADS). 0 restores the default: every
// hardware thread. Throws InputError outside [0, 4096].
void set_thread_count(std::size_t threads);
// The threads the loops below may use now.
std::size_t worker_count();
// Calls body(begin, end) for consecutive chunks of at most `chunk` indices; rethrows the first exception.
void parallel_for(std::size_t n, std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& body);

}  // namespace clr
