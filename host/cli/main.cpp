// clradiosity: exit 0 on success, 1 on a runtime failure, 2 on bad input or usage, always with one line on stderr.
// Under mpirun a failing rank names itself in that line and ends the whole job with its exit code.
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cl/error.hpp"
#include "cli/command.hpp"
#include "cli/failure_message.hpp"
#include "common/digest.hpp"
#include "common/error.hpp"
#include "common/parallel.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "distributed/communicator.hpp"
#include "radiosity/environment.hpp"
#include "radiosity/preset.hpp"

namespace clr::cli {

void add_device_option(CLI::App& cmd, std::string& spec) {
  cmd.add_option("--device", spec,
                 "OpenCL device: P:D indices or a case-insensitive substring of platform/device name or type "
                 "(pocl, nvidia, cpu, gpu); default $CLRADIOSITY_DEVICE, else the first GPU, else the first CPU");
  add_threads_option(cmd);
}

namespace {
std::string& command_line_text() {
  static std::string text;
  return text;
}
}  // namespace

const std::string& command_line() { return command_line_text(); }

std::map<std::string, std::string> exr_metadata(const std::string& scene_digest, std::optional<int> spp,
                                                std::optional<std::uint64_t> seed, std::optional<double> seconds,
                                                long long steps) {
  std::map<std::string, std::string> m = {{"software", std::string("clradiosity ") + CLR_VERSION},
                                          {"commandLine", command_line()},
                                          {"sceneDigest", scene_digest}};
  if (spp) m["spp"] = std::to_string(*spp);
  if (seed) m["seed"] = std::to_string(*seed);
  if (seconds) {
    char time[32];
    std::snprintf(time, sizeof time, "%.3f", *seconds);
    m["renderTimeSeconds"] = time;
  }
  if (steps >= 0) m["steps"] = std::to_string(steps);
  return m;
}

void add_scene_parameters_option(CLI::App& cmd, std::map<std::string, std::string>& parameters) {
  cmd.add_option_function<std::vector<std::string>>(
         "-D",
         [&parameters](const std::vector<std::string>& given) {
           for (const auto& item : given) {
             const auto eq = item.find('=');
             if (eq == std::string::npos || eq == 0)
               throw CLI::ValidationError("-D", "'" + item + "' is not key=value");
             parameters[item.substr(0, eq)] = item.substr(eq + 1);
           }
         },
         "key=value: the scene's parameter $key (over its <default>), as mitsuba -D; repeatable")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

void add_sensor_option(CLI::App& cmd, int& sensor) {
  cmd.add_option("--sensor", sensor, "Which of the scene's sensors renders, in the file's order (default 0)")
      ->check(CLI::Range(0, 1 << 20));
}

namespace {
// Every command's --threads writes here; applied once the command line is parsed (apply_thread_count).
int& threads_flag() {
  static int threads = 0;
  return threads;
}
}  // namespace

void add_threads_option(CLI::App& cmd) {
  cmd.add_option("--threads", threads_flag(),
                 "Threads for the host's stages (sampling, tracing, the path tracer) and a PoCL CPU device; default "
                 "$CLRADIOSITY_THREADS, else every hardware thread")
      ->check(CLI::Range(1, 4096));
}

// --threads, else CLRADIOSITY_THREADS, before anything starts the OpenCL platform (PoCL reads its thread count then).
void apply_thread_count() {
  int threads = threads_flag();
  if (threads == 0)
    if (const char* env = std::getenv("CLRADIOSITY_THREADS"); env && *env) {
      char* end = nullptr;
      const long n = std::strtol(env, &end, 10);
      if (*end != '\0' || n < 1 || n > 4096)
        throw InputError("CLRADIOSITY_THREADS='" + std::string(env) + "' is not a thread count in [1, 4096]");
      threads = int(n);
    }
  if (threads > 0) set_thread_count(std::size_t(threads));
}

}  // namespace clr::cli

namespace {
// Training budget of the main job: short enough for a first run, long enough for a recognisable image.
constexpr double kMainJobMinutes = 2.0;

// "rank 1: " before a failure's message in a job of several ranks, so the line names the process at fault.
std::string rank_prefix() {
  const auto& ranks = clr::distributed::Communicator::world();
  return ranks.distributed() ? "rank " + std::to_string(ranks.rank()) + ": " : "";
}

// Work that a signal stopped at a safe point ends with the exit status of a process that signal ended.
int stopped_by_signal(int code) { return code == 0 && clr::stop_signal() != 0 ? 128 + clr::stop_signal() : code; }

// Set when every rank failed at the same point (JobInputError): the job ends without an abort.
bool failed_together = false;

// The command line as the ranks must share it: every argument but the device choice, which may pin each rank to
// its own device.
std::uint64_t command_line_digest(int argc, char** argv) {
  clr::Digest digest;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--device") {
      ++i;
      continue;
    }
    if (arg.starts_with("--device=")) continue;
    digest.add(arg).add(std::string_view("\0", 1));
  }
  return digest.value();
}

int run(int argc, char** argv) {
  for (int i = 0; i < argc; ++i) clr::cli::command_line_text() += (i ? " " : "") + std::string(argv[i]);
  CLI::App app{"clradiosity: Importance-Sampling-Guided Neural Radiosity on OpenCL devices", "clradiosity"};
  app.set_version_flag("--version", std::string("clradiosity ") + CLR_VERSION);
  app.require_subcommand(0, 1);
  std::string preset;
  app.add_option("--preset", preset, "The main job (no subcommand) with a budget preset: preview, balanced, quality")
      ->check(CLI::IsMember(clr::radiosity::budget_preset_names()));
  clr::cli::add_threads_option(app);

  const std::vector<clr::cli::Command> commands = {
      clr::cli::add_devices_command(app), clr::cli::add_compare_command(app), clr::cli::add_reference_command(app),
      clr::cli::add_train_command(app),   clr::cli::add_render_command(app),  clr::cli::add_residual_command(app),
      clr::cli::add_guide_command(app),   clr::cli::add_sweep_command(app),   clr::cli::add_export_command(app),
      clr::cli::add_report_command(app),
  };
  // pbrt's --quiet: no progress and no informational lines on stderr; results (stdout) and errors stay.
  bool quiet = false;
  constexpr const char* kQuietHelp = "No progress or informational lines on stderr (results and errors stay)";
  app.add_flag("-q,--quiet", quiet, kQuietHelp);
  for (const auto& c : commands) c.app->add_flag("-q,--quiet", quiet, kQuietHelp);

  std::string command;  // names the options to lower when memory runs out
  try {
    app.parse(argc, argv);
    if (quiet) clr::Progress::silence_process();
    clr::cli::apply_thread_count();
    clr::radiosity::check_environment();
    const auto& ranks = clr::distributed::Communicator::world();
    if (ranks.distributed()) {
      const CLI::App* parsed = nullptr;
      for (const auto& c : commands)
        if (c.app->parsed()) parsed = c.app;
      const std::string name = parsed ? parsed->get_name() : "the main job";
      if (name != "train" && name != "reference")
        throw clr::distributed::JobInputError(
            name + " runs in one process: start it without mpirun (train and reference use MPI)");
      ranks.require_same("the command lines", command_line_digest(argc, argv));
    }
    for (const auto& c : commands)
      if (c.app->parsed()) {
        if (!preset.empty())
          throw clr::InputError("--preset before '" + c.app->get_name() + "' belongs to the main job; put it after it");
        command = c.app->get_name();
        return stopped_by_signal(c.run());
      }
    return stopped_by_signal(clr::cli::run_main_job(kMainJobMinutes, preset));
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "clradiosity: error: " << rank_prefix() << clr::cli::bounded_line(e.what()) << " (see --help)\n";
    return 2;
  } catch (const clr::distributed::JobInputError& e) {
    // Every rank knows; rank 0 says it once.
    failed_together = true;
    if (clr::distributed::Communicator::world().rank() == 0)
      std::cerr << "clradiosity: error: " << clr::cli::bounded_line(e.what()) << "\n";
    return 2;
  } catch (const clr::InputError& e) {
    std::cerr << "clradiosity: error: " << rank_prefix() << clr::cli::bounded_line(e.what()) << "\n";
    return 2;
  } catch (const clr::distributed::StoppedWhileWaiting& e) {
    std::cerr << "clradiosity: stopped: " << rank_prefix() << clr::cli::bounded_line(e.what()) << "\n";
    return 128 + clr::stop_signal();
  } catch (const std::filesystem::filesystem_error& e) {
    if (!clr::cli::path_at_fault(e)) {
      std::cerr << "clradiosity: failed: " << rank_prefix() << clr::cli::bounded_line(e.what()) << "\n";
      return 1;
    }
    std::cerr << "clradiosity: error: " << rank_prefix() << clr::cli::bounded_line(clr::cli::path_message(e)) << "\n";
    return 2;
  } catch (const nlohmann::json::type_error& e) {
    // Every JSON the program reads is checked where it is read; what reaches here is a record or output that
    // cannot be written: JSON holds UTF-8 only, and a file or folder name given may be any bytes (type_error 316).
    if (e.id != 316) {
      std::cerr << "clradiosity: failed: " << rank_prefix() << clr::cli::bounded_line(e.what()) << "\n";
      return 1;
    }
    std::cerr << "clradiosity: error: " << rank_prefix()
              << clr::cli::bounded_line(std::string("a file or folder name given is not valid UTF-8, which the run's "
                                                    "JSON records cannot hold: rename it (") +
                                        e.what() + ")")
              << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "clradiosity: failed: " << rank_prefix()
              << clr::cli::bounded_line(clr::cli::failure_message(e, command)) << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // What the process was started with (`nohup` ignores SIGHUP), before MPI or a runtime installs handlers of its own.
  clr::remember_signal_dispositions();
  // MPI starts before the OpenCL runtime's threads do, and only under mpirun (Communicator::world).
  auto& ranks = clr::distributed::Communicator::world();
  if (ranks.rank() != 0) clr::Progress::silence_process();
  // A closed pipe on stdout (`clradiosity devices | head -1`) would end the process by SIGPIPE without a word (exit
  // 141); ignored, a write fails instead, and the process says so in its one line.
  std::signal(SIGPIPE, SIG_IGN);
  // A library loaded with the runtimes catches SIGHUP, SIGQUIT and SIGUSR1 and then does nothing: each was silently
  // swallowed. What the process was started with comes back here (the default action, or ignored where it was);
  // the stop handlers (common/stop_signal.hpp) take them over wherever work stops at a safe point. Under mpirun the
  // MPI runtime's own handling is left alone.
  if (!ranks.distributed()) clr::reclaim_signals();
  int code = run(argc, argv);
  std::cout.flush();
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
    const int err = errno;
    std::cerr << "clradiosity: failed: writing standard output: "
              << (err == EPIPE || err == 0 ? std::string("the pipe or file was closed by its reader")
                                           : std::string(std::strerror(err)))
              << "\n";
    if (code == 0) code = 1;
  }
  return ranks.finish(code, failed_together);
}
