#pragma once
// The CLRADIOSITY_* variables the engine reads where it uses them (docs/cli.md, "Environment"), checked together
// before any work starts: a bad value is refused before a run folder, an image or a cache is written, not halfway
// through (a step schedule read by the trainer once the run's files exist). CLRADIOSITY_THREADS and
// CLRADIOSITY_MPI_TIMEOUT are the CLI's and MPI's: read first thing where they are used.
namespace clr::radiosity {

// InputError naming the first variable whose value is unusable.
void check_environment();

}  // namespace clr::radiosity
