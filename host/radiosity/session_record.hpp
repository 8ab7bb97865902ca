#pragma once
// RUN_DIR/sessions.json: what trained the run, one entry per `train` session (a fresh run, then each --resume), so
// that a run can be told apart from its settings' copy in config.json: the commit and version of the binary, the
// device, the preset's choices and their reasons (the lines `train --preset` prints), the steps and training time,
// and the session's peak device memory (the context's accounting) and peak resident memory (getrusage's
// ru_maxrss). Kept per session, not merged: a resumed run may continue under another binary or device, and each
// session's peak is its own process's. Readers (the report) show the last session's commit and the largest peaks.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace clr::radiosity {

struct SessionRecord {
  std::string software;  // "clradiosity 0.1.0"
  std::string commit;    // `git describe --always --dirty` of the build (cmake/commit_script.cmake)
  std::string finished;  // UTC, ISO 8601
  std::string device;    // cl::DeviceInfo::describe()
  std::uint64_t first_step = 0, last_step = 0;
  double training_seconds = 0;  // the run's, over every session so far (log.csv's seconds column)
  double peak_device_mib = 0;   // rank 0's OpenCL buffers at their peak in this session
  double peak_resident_mib = 0;
  bool stopped = false;  // ended by a signal before its budget
  std::string preset;    // empty: none given this session (--preset cannot be given with --resume)
  std::vector<std::string> preset_choices;
};

// This build's version and commit, the time now, and the process's peak resident memory so far; the caller fills
// the rest.
SessionRecord this_session();

// The process's peak resident set so far (getrusage ru_maxrss), in MiB; 0 where the platform does not say.
double peak_resident_mib();

nlohmann::json to_json(const SessionRecord& session);

// Appends `session` to RUN_DIR/sessions.json (written atomically). InputError naming the file when the file there
// is not a sessions record: it is left as it was rather than overwritten.
void append_session_record(const std::filesystem::path& run_dir, const SessionRecord& session);

// The sessions recorded in RUN_DIR, oldest first; empty for a run written before runs recorded them. InputError
// naming the file when it is damaged.
nlohmann::json read_session_records(const std::filesystem::path& run_dir);

}  // namespace clr::radiosity
