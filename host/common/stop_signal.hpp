#pragma once
// SIGINT/SIGTERM ask long work to stop at its next safe point (a trainer writes a checkpoint, then exits 0)
// instead of killing the process mid-write. A second signal falls back to the default action.
namespace clr {

void install_stop_handlers();
bool stop_requested();
void request_stop();  // what the handlers do; also for tests

}  // namespace clr
