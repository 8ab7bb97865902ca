#pragma once
// Each subcommand registers itself on the CLI11 app and returns the function that runs it after parsing.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace clr::cli {

// A parsed subcommand and what runs it.
struct Command {
  CLI::App* app;
  std::function<int()> run;
};

// Adds --device SPEC (docs/design.md §4) to a computing command; CLRADIOSITY_DEVICE is its default. And --threads.
void add_device_option(CLI::App& cmd, std::string& spec);
// Adds --threads N (CLRADIOSITY_THREADS): caps the host's worker pool and a PoCL device's threads.
void add_threads_option(CLI::App& cmd);
// Applies --threads or CLRADIOSITY_THREADS (InputError naming a malformed value), before any OpenCL call.
void apply_thread_count();

Command add_devices_command(CLI::App& app);
Command add_reference_command(CLI::App& app);
Command add_compare_command(CLI::App& app);
Command add_train_command(CLI::App& app);
Command add_render_command(CLI::App& app);
Command add_residual_command(CLI::App& app);
Command add_guide_command(CLI::App& app);
Command add_sweep_command(CLI::App& app);

// `clradiosity` without a subcommand: train and render the bundled Cornell box (README's first command) for
// `minutes`, or with a preset's settings and budget.
int run_main_job(double minutes, const std::string& preset);

}  // namespace clr::cli
