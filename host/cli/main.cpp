// clradiosity: exit 0 on success, 1 on a runtime failure, 2 on bad input or usage, always with one line on stderr.
#include <cstdio>
#include <exception>
#include <iostream>

#include "cl/error.hpp"
#include "cli/command.hpp"
#include "cli/failure_message.hpp"
#include "common/error.hpp"

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
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"clradiosity: Importance-Sampling-Guided Neural Radiosity on OpenCL devices", "clradiosity"};
  app.set_version_flag("--version", std::string("clradiosity ") + CLR_VERSION);
  app.require_subcommand(0, 1);

  const std::vector<clr::cli::Command> commands = {
      clr::cli::add_devices_command(app), clr::cli::add_compare_command(app), clr::cli::add_reference_command(app),
      clr::cli::add_train_command(app),   clr::cli::add_render_command(app),  clr::cli::add_residual_command(app),
      clr::cli::add_guide_command(app),
  };

  std::string command;  // names the options to lower when memory runs out
  try {
    app.parse(argc, argv);
    for (const auto& c : commands)
      if (c.app->parsed()) {
        command = c.app->get_name();
        return c.run();
      }
    return clr::cli::run_main_job(kMainJobMinutes);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "clradiosity: error: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const clr::InputError& e) {
    std::cerr << "clradiosity: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "clradiosity: failed: " << clr::cli::failure_message(e, command) << "\n";
    return 1;
  }
}
