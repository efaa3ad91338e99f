// owval pipeline SCENARIO -o DIR: phases 1-8 on one scenario (the pipeline library), into one
// report directory whose layout is the PR checklist's (docs/checklist.md).
#include <cstdio>

#include "command.hpp"
#include "owval/pipeline/pipeline.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {

void RunPipeline(pipeline::Options& o, bool json) {
  o.quiet = QuietMode();
  o.on_phase = [](const std::string& line) {
    if (!QuietMode()) std::fprintf(stderr, "pipeline: %s\n", line.c_str());
  };
  pipeline::Summary summary;
  pipeline::Run(o, &summary);
  if (json)
    std::cout << summary.ToJson().dump(2) << "\n";
  else
    std::cout << "report: " << summary.index_html.string() << "\n"
              << summary.checklist.ToMarkdown();
  SetExitCode(summary.exit_code());
}

void SetUpPipeline(CLI::App& app) {
  auto o = std::make_shared<pipeline::Options>();
  o->data_dir = DataDir();
  CLI::App* cmd = app.add_subcommand(
      "pipeline", "Phases 1-8 on one scenario: report directory, MP4, checklist");
  AddInput(cmd, "scenario", &o->scenario, "Built-in scenario (owval scenario list)");
  AddOut(cmd, &o->out_dir, "Report directory (default reports/SCENARIO)");
  cmd->add_option("--candidate", o->candidate,
                  "Candidate trajectory file instead of an owval engine run");
  auto integrator = std::make_shared<std::string>("euler");
  AddIntegratorFlag(cmd, integrator.get(), " of the candidate engine");
  AddBackendFlag(cmd, &o->backend,
                 " of the candidate: pcisph, xpbd or wcsph; xpbd: phase 5 runs owval gradcheck");
  cmd->add_option("--max-video-frames", o->max_video_frames,
                  "Frames in sxs.mp4, evenly spaced (0: every frame)");
  auto json = std::make_shared<bool>(false);
  AddJsonFlag(cmd, json.get(), "the phases, parity and checklist");
  cmd->callback([o, integrator, json] {
    o->integrator = engine::ParseIntegrator(*integrator);
    RunPipeline(*o, *json);
  });
}

const bool pipeline_registered = RegisterCommand(&SetUpPipeline);

}  // namespace
}  // namespace owval::cli
