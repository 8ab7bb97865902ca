// clradiosity export RUN_DIR -o MODEL.safetensors [--weights-only]
#include <cstdio>
#include <filesystem>

#include "cli/command.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "radiosity/model_export.hpp"
#include "radiosity/run_directory.hpp"

namespace clr::cli {

Command add_export_command(CLI::App& app) {
  struct Options {
    std::string run, out;
    bool weights_only = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("export",
                                 "Write a run's networks as a safetensors file (PyTorch, JAX, numpy): every tensor "
                                 "named, the networks' configs and encodings in its metadata");
  cmd->add_option("run", opt->run, "Run directory written by `train` (or its model.clr)")->required();
  cmd->add_option("-o", opt->out, "Output (.safetensors)")->required();
  cmd->add_flag("--weights-only", opt->weights_only, "Leave out the optimiser's state (the Adam moments)");

  return {cmd, [opt]() {
            const std::filesystem::path out = opt->out;
            // The extension says the format, as for every output; a model under another name would mislead.
            if (out.extension() != ".safetensors")
              throw InputError("-o " + opt->out + ": the output must end in .safetensors");
            require_outputs({{out, "-o"}}, radiosity::RunDirectory::input_files(opt->run));
            const auto file = radiosity::export_model(opt->run, !opt->weights_only);
            nn::write_safetensors(out, file);
            std::size_t values = 0;
            for (const auto& t : file.tensors) values += t.values.size();
            std::printf("%s: %zu tensors, %zu values (step %s)\n", opt->out.c_str(), file.tensors.size(), values,
                        file.metadata.at("step").c_str());
            return 0;
          }};
}

}  // namespace clr::cli
