// clradiosity: exit 0 on success, 1 on a runtime failure, 2 on bad input or usage, always with one line on stderr.
// Under mpirun a failing rank names itself in that line and ends the whole job with its exit code.
#include <cstdio>
#include <exception>
#include <iostream>

#include "cl/error.hpp"
#include "cli/command.hpp"
#include "cli/failure_message.hpp"
#include "common/error.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "distributed/communicator.hpp"
#include "radiosity/preset.hpp"

namespace clr::cli {

void add_device_option(CLI::App& cmd, std::string& spec) {
  cmd.add_option("--device", spec,
                 "OpenCL device: P:D indices or a case-insensitive substring of platform/device name or type "
                 "(pocl, nvidia, cpu, gpu); default $CLRADIOSITY_DEVICE, else the first GPU, else the first CPU");
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

int run(int argc, char** argv) {
  CLI::App app{"clradiosity: Importance-Sampling-Guided Neural Radiosity on OpenCL devices", "clradiosity"};
  app.set_version_flag("--version", std::string("clradiosity ") + CLR_VERSION);
  app.require_subcommand(0, 1);
  std::string preset;
  app.add_option("--preset", preset, "The main job (no subcommand) with a budget preset: preview, balanced, quality")
      ->check(CLI::IsMember(clr::radiosity::preset_names()));

  const std::vector<clr::cli::Command> commands = {
      clr::cli::add_devices_command(app), clr::cli::add_compare_command(app), clr::cli::add_reference_command(app),
      clr::cli::add_train_command(app),   clr::cli::add_render_command(app),  clr::cli::add_residual_command(app),
      clr::cli::add_guide_command(app),   clr::cli::add_sweep_command(app),
  };

  std::string command;  // names the options to lower when memory runs out
  try {
    app.parse(argc, argv);
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
    std::cerr << "clradiosity: error: " << rank_prefix() << e.what() << " (see --help)\n";
    return 2;
  } catch (const clr::InputError& e) {
    std::cerr << "clradiosity: error: " << rank_prefix() << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "clradiosity: failed: " << rank_prefix() << clr::cli::failure_message(e, command) << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // MPI starts before the OpenCL runtime's threads do, and only under mpirun (Communicator::world).
  auto& ranks = clr::distributed::Communicator::world();
  if (ranks.rank() != 0) clr::Progress::silence_process();
  return ranks.finish(run(argc, argv));
}
