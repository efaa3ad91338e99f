// owval convert IN OUT: between Sibernetic text layouts and owval's HDF5.
#include <cstdio>

#include "command.hpp"
#include "owval/pipeline/run_directory.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct ConvertArgs {
  std::string in, out;
  std::string layout = "auto";
  std::string out_layout = "opencl";
};

void RunConvert(const ConvertArgs& a) {
  TextReadReport read;
  pipeline::ConvertTrajectoryFile(a.in, Reading(a.layout), a.out, ParseLayout(a.out_layout), &read);
  if (!QuietMode())
    std::fprintf(stderr, "read %s (%s), wrote %s\n", a.in.c_str(), read.description.c_str(),
                 a.out.c_str());
}

void SetUpConvert(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app.add_subcommand("convert",
                                     "Convert trajectories: opencl/native text <-> HDF5 (.h5); "
                                     "worm to WCON (.wcon) or OME-Zarr (.zarr)");
  AddInput(cmd, "input", &args->in, "Input trajectory");
  cmd->add_option("output", args->out,
                  "Output by extension: .h5/.hdf5 (owval HDF5), .txt (Sibernetic text), .wcon "
                  "(WCON, worms), .zarr (OME-Zarr); other extensions are refused")
      ->required()
      ->check(OutputPath());
  AddLayoutFlag(cmd, &args->layout);
  cmd->add_option("--out-layout", args->out_layout, "Output text layout: opencl or native")
      ->check(CLI::IsMember({"opencl", "native"}));
  cmd->callback([args] { RunConvert(*args); });
}

const bool convert_registered = RegisterCommand(&SetUpConvert);

}  // namespace
}  // namespace owval::cli
