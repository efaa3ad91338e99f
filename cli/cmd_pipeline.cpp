// owval pipeline SCENARIO -o DIR: phases 1-8 on one scenario (the pipeline library), into one
// report directory whose layout is the PR checklist's (docs/checklist.md).
#include <cstdio>
#include <iostream>

#include "command.hpp"
#include "owval/pipeline/pipeline.hpp"

namespace owval::cli {
namespace {

struct PipelineArgs {
  std::string scenario, out, candidate;
  std::string integrator = "euler";
  std::string backend = "pcisph";
  std::size_t max_video_frames = 300;
};

void RunPipeline(const PipelineArgs& a) {
  pipeline::Options o;
  o.scenario = a.scenario;
  o.data_dir = DataDir();
  o.out_dir =
      a.out.empty() ? std::filesystem::path("reports") / a.scenario : std::filesystem::path(a.out);
  o.candidate = a.candidate;
  o.integrator = a.integrator == "leapfrog" ? engine::Integrator::kLeapfrog
                                            : engine::Integrator::kSemiImplicitEuler;
  o.backend = a.backend;
  o.max_video_frames = a.max_video_frames;
  o.quiet = Flags().quiet;
  o.on_phase = [](const std::string& line) {
    if (!Flags().quiet) std::fprintf(stderr, "pipeline: %s\n", line.c_str());
  };
  pipeline::Summary summary;
  pipeline::Run(o, &summary);
  std::cout << "report: " << summary.index_html.string() << "\n" << summary.checklist.ToMarkdown();
  SetExitCode(summary.exit_code());
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<PipelineArgs>();
  CLI::App* cmd = app.add_subcommand(
      "pipeline", "Phases 1-8 on one scenario: report directory, MP4, checklist");
  cmd->add_option("scenario", a->scenario, "Built-in scenario (owval scenario list)")->required();
  cmd->add_option("-o,--out", a->out, "Report directory (default reports/SCENARIO)");
  cmd->add_option("--candidate", a->candidate,
                  "Candidate trajectory file instead of an owval engine run");
  cmd->add_option("--integrator", a->integrator, "Candidate engine integrator: euler or leapfrog")
      ->check(CLI::IsMember({"euler", "leapfrog"}));
  cmd->add_option("--backend", a->backend,
                  "Candidate scheme (pcisph, xpbd, wcsph); xpbd: phase 5 runs owval gradcheck");
  cmd->add_option("--max-video-frames", a->max_video_frames,
                  "Frames in sxs.mp4, evenly spaced (0: every frame)");
  cmd->callback([a] { RunPipeline(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
