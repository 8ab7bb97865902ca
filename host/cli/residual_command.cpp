// clradiosity residual SCENE.xml --model RUN_DIR [--points P --samples S] [--sampling bsdf|guide] [--nee on|off]
//                     [--json]
// Prints the means over all points, then over each material's (JSON: "materials").
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cl/context.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "geometry/geometry.hpp"
#include "radiosity/residual.hpp"
#include "radiosity/run_directory.hpp"
#include "radiosity/train_config.hpp"
#include "radiosity/trained_model.hpp"
#include "scene/fingerprint.hpp"

namespace clr::cli {

Command add_residual_command(CLI::App& app) {
  struct Options {
    std::string scene, model, device, sampling = "bsdf", nee;
    std::map<std::string, std::string> parameters;
    float bsdf_fraction = -1;
    std::size_t points = 1 << 16, samples = 256;
    std::uint64_t seed = 7;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("residual", "Mean squared rendering-equation residual of a trained model");
  cmd->add_option("scene", opt->scene, "Mitsuba scene (XML)")->required();
  cmd->add_option("--model", opt->model, "Run directory written by `train` (or a model.clr file)")->required();
  cmd->add_option("--points", opt->points, "Random (x, ω_o) points (default 65536)")->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--samples", opt->samples, "Incident samples per point (default 256)")->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--sampling", opt->sampling,
                  "bsdf (default) or guide: the one-sample mixture with the run's I-Module, as training draws them")
      ->check(CLI::IsMember({"bsdf", "guide"}));
  cmd->add_option("--bsdf-fraction", opt->bsdf_fraction, "BSDF share of the guided mixture (default: the run's)")
      ->check(finite_in(0, 1, true));
  cmd->add_option("--nee", opt->nee,
                  "Next-event estimation of area lights and the environment beside the directions, as training draws "
                  "it: on or off (default: the run's setting)")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--seed", opt->seed, "Random seed")->check(integer_at_least(0));
  cmd->add_flag("--json", opt->json, "Print one JSON object");
  add_device_option(*cmd, opt->device);
  add_scene_parameters_option(*cmd, opt->parameters);

  return {cmd, [opt]() {
            const auto scene = scene::load_scene(opt->scene, opt->parameters);
            radiosity::RunDirectory::require_scene(opt->model, scene::fingerprint(scene));
            const geometry::Geometry geometry(scene);
            cl::Context ctx(cl::select_device(opt->device));
            const std::filesystem::path model = opt->model;
            auto network = radiosity::RunDirectory::load_radiance(ctx, model);
            std::unique_ptr<nn::Network> guide;
            const auto run = std::filesystem::is_directory(model) ? model : model.parent_path();
            const radiosity::TrainConfig config = radiosity::RunDirectory::load_config(run);
            float fraction = opt->bsdf_fraction;
            if (opt->sampling == "guide") {
              guide = radiosity::RunDirectory::load_guide(ctx, run);
              if (fraction < 0) fraction = float(config.bsdf_fraction);
            }
            const bool nee = opt->nee.empty() ? config.nee : opt->nee == "on";
            const auto r = radiosity::measure_residual(ctx, geometry, *network, opt->points, opt->samples, opt->seed,
                                                       guide.get(), fraction, nee);
            nlohmann::json materials = nlohmann::json::array();
            for (std::size_t k = 0; k < r.by_material.size(); ++k)
              if (const auto& part = r.by_material[k]; part.points)
                materials.push_back({{"material", k},
                                     {"roughness", scene.materials[k]->roughness()},
                                     {"points", part.points},
                                     {"residual", part.mean},
                                     {"rhs_variance", part.rhs_variance}});
            if (opt->json) {
              std::cout << nlohmann::json{{"residual", r.mean},
                                          {"standard_error", r.standard_error},
                                          {"rhs_variance", r.rhs_variance},
                                          {"sampling", opt->sampling},
                                          {"nee", nee},
                                          {"points", r.points},
                                          {"samples", opt->samples},
                                          {"materials", materials}}
                               .dump()
                        << "\n";
              return 0;
            }
            std::printf("residual %.6g ± %.2g, one-sample RHS variance %.6g (P = %zu, S = %zu, %s sampling, NEE %s)\n",
                        r.mean, r.standard_error, r.rhs_variance, r.points, opt->samples, opt->sampling.c_str(),
                        nee ? "on" : "off");
            if (materials.size() > 1)
              for (const auto& m : materials) {
                // Each material's share of the points and of the variance's total: which surfaces carry it.
                const double points = m["points"], v = m["rhs_variance"];
                std::printf(
                    "  material %zu (roughness %.3g): %.1f %% of the points, residual %.4g, variance %.4g "
                    "(%.1f %% of the total)\n",
                    std::size_t(m["material"]), float(m["roughness"]), 100 * points / double(r.points),
                    double(m["residual"]), v,
                    r.rhs_variance > 0 ? 100 * points * v / (double(r.points) * r.rhs_variance) : 0.0);
              }
            return 0;
          }};
}

}  // namespace clr::cli
