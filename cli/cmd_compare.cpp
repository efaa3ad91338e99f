// owval compare REF CAND: the parity report a backend port must pass (exit 1 when a gate fails).
// REF and CAND are trajectory files, or backend names (backends/suite.hpp: every scenario run or
// fetched on both sides); backends/commands.hpp tells them apart.
#include <cstdio>

#include "backend_flags.hpp"
#include "command.hpp"

namespace owval::cli {
namespace {

struct CompareArgs {
  backends::CompareRequest request;
  std::string suite;
  bool json = false;
};

// The gates themselves are said by each threshold's flag (compare::kGateThresholdFields), so a
// new gate's help cannot be missing here.
const char* kGatesHelp =
    "Gates: each printed with value, threshold and source; flags override a --manifest's "
    "\"gates\", which override the defaults given with each flag, and each threshold's flag "
    "above says what its gate measures (docs/checklist.md has the table). period and "
    "half_amplitude apply only when both signals have --min-crossings upward mean crossings; "
    "worm.* when both runs are worms; liquid.fraction_above_membrane for liquid over an elastic "
    "sheet (demo2); liquid_packing when the reference has liquid; elastic.bond_length when it "
    "has an elastic body; else n/a. Both runs are "
    "measured over their common time window only, and frames pair only where their times meet.";

void RunCompare(CompareArgs& a) {
  backends::CompareRequest& r = a.request;
  r.reading.quiet = QuietMode();
  if (!QuietMode())
    r.on_progress = [](const std::string& s) { std::fprintf(stderr, "compare: %s\n", s.c_str()); };
  const backends::CompareOutcome outcome = backends::CompareNamed(r);
  for (const std::string& note : outcome.notes)  // as render's: --quiet silences progress only
    std::fprintf(stderr, "owval: note: %s\n", note.c_str());
  PrintReport(outcome, a.json, &backends::CompareOutcome::ToTable);
}

void SetUpCompare(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  backends::CompareRequest& r = args->request;
  r.scenarios.shared_reference = SharedReference();
  r.scenarios.data_dir = DataDir();
  r.thresholds.resize(compare::kGateThresholdFields.size());
  CLI::App* cmd = app.add_subcommand(
      "compare", "Phase 7: frame-by-frame parity of a candidate against a reference");
  cmd->footer(kGatesHelp);
  AddInput(cmd, "reference", &r.reference, "Reference trajectory file or backend name");
  AddInput(cmd, "candidate", &r.candidate, "Candidate trajectory file or backend name");
  AddBackendFlags(cmd, &r.backends, true);
  cmd->add_option("--scenarios", r.scenarios.names, "With backend names: these scenarios only")
      ->delimiter(',');
  cmd->add_option("--suite", args->suite,
                  "With backend names: parity = every scenario with a configuration (default)")
      ->check(CLI::IsMember({"parity"}));
  AddReferenceDir(cmd, &r.scenarios.reference_dir,
                  "With backend names: ", "the store of either backend, else ../shared/reference");
  cmd->add_option("--sibernetic", r.scenarios.sibernetic,
                  "With backend names: Sibernetic's demos from this checkout of "
                  "openworm/sibernetic (default: $SIBERNETIC_HOME), by scenarios/sibernetic/")
      ->check(GivenName());
  AddBackendSets(cmd, &r.sets, "With backend names: ");
  AddTrackFlags(cmd, &r.track, "", "Tracked");
  cmd->add_option("--frames", r.frames,
                  "Reference frames to gate, e.g. 0,15,100,200 (default: all paired)");
  cmd->add_option("--scale", r.scale, "Scale for the frame gate in cu (default: reference range)")
      ->check(Positive());
  for (std::size_t i = 0; i < r.thresholds.size(); ++i)
    cmd->add_option(compare::kGateThresholdFields[i].flag, r.thresholds[i],
                    compare::GateThresholdHelp(compare::kGateThresholdFields[i]))
        ->check(Positive());
  cmd->add_option("--manifest", r.manifest, "Scenario manifest JSON (its track and gates)")
      ->check(GivenName());
  AddMarkdownOut(cmd, &r.markdown, "the report");
  AddJsonFlag(cmd, &args->json);
  cmd->callback([args] { RunCompare(*args); });
}

const bool compare_registered = RegisterCommand(&SetUpCompare);

}  // namespace
}  // namespace owval::cli
