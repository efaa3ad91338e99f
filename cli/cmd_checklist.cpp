// owval checklist DIR: the PR checklist bot (Markdown comment, exit 1 when not ready).
#include <iomanip>
#include <iostream>

#include "backend_flags.hpp"
#include "command.hpp"
#include "owval/base/format.hpp"
#include "owval/pipeline/checklist_request.hpp"

namespace owval::cli {
namespace {

struct ChecklistArgs {
  pipeline::ChecklistRequest request;
  bool json = false;
};

void RunChecklistCommand(const ChecklistArgs& a) {
  const ci::ChecklistReport report = pipeline::CheckDirectory(a.request);
  // The JSON streamed out, not first built as one string (a 25,000-frame parity report is 7 MB).
  if (a.json)
    std::cout << std::setw(2) << report.ToJson() << "\n";
  else
    std::cout << report.ToMarkdown();
  SetExitCode(report.exit_code());
}

void SetUpChecklist(CLI::App& app) {
  auto args = std::make_shared<ChecklistArgs>();
  pipeline::ChecklistRequest& r = args->request;
  r.data_dir = DataDir();
  CLI::App* cmd = app.add_subcommand(
      "checklist",
      "Phase 8: the 10-item PR checklist and the parity gate over an artifact directory");
  cmd->footer(
      "Verdict: ready (exit 0) when all ten items and the parity gate pass; incomplete but not "
      "blocking (exit 0) when only items 7-10 fail; not ready (exit 1) when item 1, 4, 5, 6 or "
      "the parity gate fails; unreviewable (exit 1) when item 2 or 3 fails. Item 2 needs the "
      "caller's reference (--scenario or --reference): the directory's own could be its "
      "candidate. Gate thresholds come from --scenario or --manifest (else DD001's defaults), "
      "never from the directory itself.");
  AddInput(cmd, "directory", &r.directory, "PR artifact directory (see docs/checklist.md)");
  auto* scenario = cmd->add_option("--scenario", r.scenario,
                                   "Built-in scenario whose track, gates and reference apply (the "
                                   "directory's reference must be the scenario's)")
                       ->check(GivenName());
  cmd->add_option("--manifest", r.manifest, "Scenario manifest JSON whose track and gates apply")
      ->excludes(scenario)
      ->check(GivenName());
  cmd->add_option("--reference", r.reference,
                  "Trajectory the directory's reference must be (another scenario's trusted run, "
                  "e.g. ../shared/reference/demo1/position_buffer.txt)")
      ->excludes(scenario)
      ->check(GivenName());
  cmd->add_option("--git-range", r.git_range,
                  "BASE..HEAD: check that prediction.json was committed before the trajectories");
  cmd->add_option("--fit-backend", r.fit_backend,
                  "Item 6: rerun a fit of a named backend through this entry of YOUR registry "
                  "(--backends), never the command the history records")
      ->check(GivenName());
  AddBackendsFileFlag(cmd, &r.backends_file, " of --fit-backend");
  cmd->add_option("--fit-rerun-tolerance", r.fit_rerun_tolerance,
                  "Item 6: relative tolerance of the rerun's residuals and loss (default " +
                      FormatNumber(r.fit_rerun_tolerance) + ")")
      ->check(Positive());
  AddMarkdownOut(cmd, &r.markdown, "the comment");
  AddJsonFlag(cmd, &args->json, "the checklist");
  cmd->callback([args] { RunChecklistCommand(*args); });
}

const bool checklist_registered = RegisterCommand(&SetUpChecklist);

}  // namespace
}  // namespace owval::cli
