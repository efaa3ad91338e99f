// owval checklist DIR: the PR checklist bot (Markdown comment, exit 1 when not ready).
#include <iomanip>
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/ci/checklist.hpp"
#include "owval/pipeline/pipeline.hpp"
#include "owval/scenarios/scenario.hpp"

namespace owval::cli {
namespace {

struct ChecklistArgs {
  std::string directory;
  std::string scenario, manifest, reference, git_range;
  std::string markdown;
  bool json = false;
};

void RunChecklistCommand(const ChecklistArgs& a) {
  ci::ChecklistOptions options;
  const compare::ParityOptions parity =
      scenarios::ParityOptionsFrom(a.scenario, a.manifest, DataDir());
  options.gates = parity.gates;
  if (!a.scenario.empty() || !a.manifest.empty()) options.track = parity.track;
  options.git_range = a.git_range;
  if (!a.markdown.empty()) {
    CheckOutputPath(a.markdown);
    std::vector<std::filesystem::path> inputs = ci::EvidenceFiles(a.directory);
    inputs.insert(inputs.end(), {a.manifest, a.reference});
    CheckOutputIsNotAnInput(a.markdown, inputs);
  }
  pipeline::ScenarioReference reference;  // its temporary file lives until the checklist is done
  if (!a.scenario.empty()) {
    reference = pipeline::MakeScenarioReference(a.scenario, DataDir());
    options.caller_reference = reference.file;
    options.caller_reference_source = a.scenario + "'s " + reference.source;
    options.scenario_prediction = pipeline::MakeScenarioPrediction(a.scenario, DataDir());
  } else if (!a.reference.empty()) {
    options.caller_reference = a.reference;
    options.caller_reference_source = a.reference;
  }
  const ci::ChecklistReport report = ci::RunChecklist(a.directory, options);
  if (!a.markdown.empty()) WriteFileAtomically(a.markdown, report.ToMarkdown());
  // The JSON streamed out, not first built as one string (a 25,000-frame parity report is 7 MB).
  if (a.json)
    std::cout << std::setw(2) << report.ToJson() << "\n";
  else
    std::cout << report.ToMarkdown();
  SetExitCode(report.exit_code());
}

void SetUp(CLI::App& app) {
  auto args = std::make_shared<ChecklistArgs>();
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
  cmd->add_option("directory", args->directory, "PR artifact directory (see docs/checklist.md)")
      ->required();
  auto* scenario = cmd->add_option("--scenario", args->scenario,
                                   "Built-in scenario whose track, gates and reference apply (the "
                                   "directory's reference must be the scenario's)");
  cmd->add_option("--manifest", args->manifest,
                  "Scenario manifest JSON whose track and gates apply")
      ->excludes(scenario);
  cmd->add_option("--reference", args->reference,
                  "Trajectory the directory's reference must be (another scenario's trusted run, "
                  "e.g. ../shared/reference/demo1/position_buffer.txt)")
      ->excludes(scenario);
  cmd->add_option("--git-range", args->git_range,
                  "BASE..HEAD: check that prediction.json was committed before the trajectories");
  cmd->add_option("--markdown", args->markdown, "Also write the Markdown comment to this file");
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args] { RunChecklistCommand(*args); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
