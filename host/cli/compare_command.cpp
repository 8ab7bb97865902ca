// clradiosity compare IMAGE.exr REFERENCE.exr [--json] [--error-map OUT.png]
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/command.hpp"
#include "common/atomic_file.hpp"
#include "image/image.hpp"
#include "image/image_format.hpp"

namespace clr::cli {

Command add_compare_command(CLI::App& app) {
  struct Options {
    std::string image, reference, error_map;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("compare",
                                 "Print MAPE, MSE and relMSE of an image against a reference (the reference is "
                                 "box-downsampled when its size is an integer multiple of the image's)");
  cmd->add_option("image", opt->image, "Image to evaluate (EXR)")->required();
  cmd->add_option("reference", opt->reference, "Reference (EXR)")->required();
  cmd->add_flag("--json", opt->json, "Print one JSON object");
  cmd->add_option("--error-map", opt->error_map, "Write a false-colour relative-error map (PNG; red = 100 %)");

  return {cmd, [opt]() {
            image::output_format(opt->error_map, "--error-map", {image::Format::Png});
            require_outputs({{opt->error_map, "--error-map"}}, {opt->image, opt->reference});
            const auto img = image::read_exr(opt->image);
            const auto ref = image::match_size(image::read_exr(opt->reference), img);
            image::require_usable_reference(ref, opt->reference);
            const auto m = image::compare(img, ref);
            if (!opt->error_map.empty()) image::write_png(opt->error_map, image::error_map(img, ref));
            if (opt->json) {
              std::cout << nlohmann::json{{"mape", m.mape},
                                          {"mse", m.mse},
                                          {"relmse", m.relmse},
                                          {"mean_ratio", m.mean_ratio},
                                          {"non_finite", m.non_finite},
                                          {"reference_non_finite", m.reference_non_finite},
                                          {"width", img.width},
                                          {"height", img.height}}
                               .dump()
                        << "\n";
            } else {
              std::printf("%s  (%dx%d)\n", image::describe(m).c_str(), img.width, img.height);
            }
            return 0;
          }};
}

}  // namespace clr::cli
