#pragma once
// Each subcommand registers itself on the CLI11 app and returns the function that runs it after parsing.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>

namespace clr::report {
struct RunReportOptions;  // report/run_report.hpp; declared only, so that the commands need not include the room
}

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
// Adds -D key=value (repeatable), Mitsuba's: fills the scene's $key where its file reads one, over its <default>.
// The values become part of the scene's fingerprint (runs and sweeps record them).
void add_scene_parameters_option(CLI::App& cmd, std::map<std::string, std::string>& parameters);
// Adds --sensor INDEX: which of the scene's sensors, in the file's order, renders (default 0, the first).
void add_sensor_option(CLI::App& cmd, int& sensor);
// The command line as given (argv joined by spaces), for the metadata of the images a command writes.
const std::string& command_line();
// What an EXR records of how it was made (docs/cli.md, "EXR metadata"): software, command line, scene digest, and
// where they apply spp, seed, seconds and `steps` (model renders). A guide map has no spp or seed; a walkthrough's
// frames, rendered back to back, no time of their own.
std::map<std::string, std::string> exr_metadata(const std::string& scene_digest, std::optional<int> spp,
                                                std::optional<std::uint64_t> seed, std::optional<double> seconds,
                                                long long steps = -1);
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
Command add_export_command(CLI::App& app);
Command add_report_command(CLI::App& app);
// The report page of a run (report/run_report.hpp) into `out`, written atomically, with its images' metrics and
// the page's size on stdout: `report` and `train --report`.
void write_run_report(const report::RunReportOptions& options, const std::filesystem::path& out);

// `clradiosity` without a subcommand: train and render the bundled Cornell box (README's first command) for
// `minutes`, or with a preset's settings and budget.
int run_main_job(double minutes, const std::string& preset);

}  // namespace clr::cli
