// owval bench render: render + H.264 encode frames per second (render/render_benchmark.hpp).
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/render/render_benchmark.hpp"

namespace owval::cli {
namespace {

void SetUp(CLI::App& app) {
  auto o = std::make_shared<render::RenderBenchmarkOptions>();
  auto json_out = std::make_shared<std::string>();
  CLI::App* cmd =
      Bench(app).add_subcommand("render", "Render + H.264 encode frames per second (JSON)");
  cmd->add_option("--frames", o->frames, "Frames per case");
  cmd->add_option("--json-out", *json_out, "Also write the JSON result here");
  cmd->callback([o, json_out] {
    if (!json_out->empty()) CheckOutputPath(*json_out);
    o->demo1_trajectory =
        std::filesystem::path(OWVAL_SHARED_DIR) / "reference/demo1/position_buffer.txt";
    const std::string result = render::RunRenderBenchmark(*o).dump(2) + "\n";
    std::cout << result;
    if (!json_out->empty()) WriteFileAtomically(*json_out, result);
  });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
