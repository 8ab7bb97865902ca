// clradiosity residual SCENE.xml --model RUN_DIR [--points P --samples S] [--json]
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cl/context.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "geometry/geometry.hpp"
#include "radiosity/residual.hpp"
#include "radiosity/trained_model.hpp"
#include "scene/scene.hpp"

namespace clr::cli {

Command add_residual_command(CLI::App& app) {
  struct Options {
    std::string scene, model, device;
    std::size_t points = 1 << 16, samples = 256;
    std::uint64_t seed = 7;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("residual", "Mean squared rendering-equation residual of a trained model");
  cmd->add_option("scene", opt->scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("--model", opt->model, "Run directory written by `train` (or a model.clr file)")->required();
  cmd->add_option("--points", opt->points, "Random (x, ω_o) points (default 65536)")->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--samples", opt->samples, "BSDF samples per point (default 256)")->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--seed", opt->seed, "Random seed")->check(integer_at_least(0));
  cmd->add_flag("--json", opt->json, "Print one JSON object");
  add_device_option(*cmd, opt->device);

  return {cmd, [opt]() {
            const auto scene = scene::load_scene(opt->scene);
            const geometry::Geometry geometry(scene);
            cl::Context ctx(cl::select_device(opt->device));
            std::filesystem::path model = opt->model;
            if (std::filesystem::is_directory(model)) model /= "model.clr";
            auto network = radiosity::load_network(ctx, model);
            const auto r = radiosity::measure_residual(ctx, geometry, *network, opt->points, opt->samples, opt->seed);
            if (opt->json)
              std::cout << nlohmann::json{{"residual", r.mean},
                                          {"standard_error", r.standard_error},
                                          {"points", r.points},
                                          {"samples", opt->samples}}
                               .dump()
                        << "\n";
            else
              std::printf("residual %.6g ± %.2g (P = %zu, S = %zu)\n", r.mean, r.standard_error, r.points,
                          opt->samples);
            return 0;
          }};
}

}  // namespace clr::cli
