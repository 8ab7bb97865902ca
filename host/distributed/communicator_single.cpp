// The communicator of a build without MPI: every job is one process, and each collective returns its input.
#include "distributed/communicator.hpp"

namespace clr::distributed {

Communicator Communicator::make_world() { return {}; }

Communicator& Communicator::world() {
  static Communicator world = make_world();
  return world;
}

Communicator& Communicator::single() { return world(); }

void Communicator::sum(std::span<float>) const {}
void Communicator::sum(std::span<double>) const {}
void Communicator::sum(std::span<std::int64_t>) const {}
void Communicator::bitwise_or(std::span<std::uint32_t>) const {}
double Communicator::max(double value) const { return value; }
void Communicator::keep_alive() const {}
void Communicator::broadcast(std::string&) const {}
void Communicator::broadcast(std::span<std::uint64_t>) const {}
void Communicator::broadcast(std::span<float>) const {}
std::vector<float> Communicator::gather(std::span<const float> part) const { return {part.begin(), part.end()}; }
void Communicator::require_same(const std::string&, std::uint64_t) const {}
int Communicator::finish(int code, bool) { return code; }

}  // namespace clr::distributed
