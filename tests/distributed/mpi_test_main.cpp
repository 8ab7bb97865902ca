// main of clr_mpi_tests, which ctest runs as `mpirun -np 2 clr_mpi_tests`: MPI lives for the whole test run, and a
// rank whose tests failed ends the job with its exit code rather than leaving the other waiting in a collective.
#include <gtest/gtest.h>

#include "common/progress.hpp"
#include "distributed/communicator.hpp"

int main(int argc, char** argv) {
  auto& ranks = clr::distributed::Communicator::world();
  if (ranks.rank() != 0) clr::Progress::silence_process();
  ::testing::InitGoogleTest(&argc, argv);
  return ranks.finish(RUN_ALL_TESTS());
}
