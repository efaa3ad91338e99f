// owval compare REF CAND: the parity report a backend port must pass (exit 1 when a gate fails).
// REF and CAND are trajectory files, or backend names (backends/suite.hpp: every scenario run or
// fetched on both sides).
#include <filesystem>
#include <iostream>

#include "backend_flags.hpp"
#include "command.hpp"
#include "owval/backends/suite.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/compare/parity.hpp"
#include "owval/scenarios/scenario.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct CompareArgs {
  std::string reference, candidate;
  TrackFlags track;
  std::string frames;
  std::optional<double> scale;
  std::string manifest;
  std::string markdown;
  bool json = false;
  BackendFlags backends;
  std::vector<std::string> scenarios, sets;
  std::string suite, reference_dir, sibernetic;
  // Gate thresholds given as flags, by the ParityGates member they set.
  std::vector<std::pair<compare::Threshold compare::ParityGates::*, std::optional<double>>> gates;
};

const char* kGatesHelp =
    "Gates (each printed with value, threshold and source; flags override a --manifest's "
    "\"gates\", which override the defaults given with each flag): frames: |cand-ref|/reference "
    "range of the tracked scalar at each gated frame; period and half_amplitude: relative gaps, "
    "applied only when both signals have --min-crossings upward mean crossings (else n/a); per "
    "group (elastic, liquid): centroid_distance (max over time), extent (max |extent difference| "
    "per axis), final_distance (last frame), fractions of the box; particle_distance.initial/"
    "mean/final of moving particles. Worms (both runs): worm.centre_of_mass (of the box), "
    "worm.span and worm.cross_section_diameter (relative). Liquid over an elastic sheet (demo2): "
    "liquid.fraction_above_membrane difference. Both runs are measured over their common time "
    "window only.";

compare::ParityOptions Options(const CompareArgs& a) {
  compare::ParityOptions o;
  if (!a.manifest.empty()) scenarios::ApplyManifestFile(a.manifest, &o);
  o.track = a.track.Over(o.track);
  if (!a.frames.empty()) o.sample_frames = ParseIndexList(a.frames, "--frames");
  o.scale = a.scale;
  for (const auto& [member, value] : a.gates)
    if (value) o.gates.*member = {*value, compare::ThresholdSource::kFlag};
  return o;
}

void CheckMarkdownOut(const CompareArgs& a) {
  CheckOutputPath(a.markdown);
  CheckOutputIsNotAnInput(a.markdown, {a.reference, a.candidate, a.manifest});
}

void RunBackendCompare(const CompareArgs& a) {
  if (!a.markdown.empty()) CheckMarkdownOut(a);
  for (const std::string& arg : {a.reference, a.candidate}) {
    std::error_code ec;
    if (arg.find('/') != std::string::npos && !std::filesystem::is_regular_file(arg, ec))
      throw InputError(arg, 0, "no such trajectory file (and not a backend name)");
  }
  const backends::Registry registry = a.backends.Registry();
  const backends::Backend& ref = registry.Find(a.reference);
  const backends::Backend& cand = registry.Find(a.candidate);
  backends::SuiteOptions options;
  backends::SelectScenarios(ref, cand,
                            {a.scenarios, a.sibernetic, a.reference_dir,
                             std::filesystem::path(OWVAL_SHARED_DIR) / "reference", DataDir()},
                            &options);
  options.sets = ParseSets(a.sets);
  if (!Flags().quiet)
    options.on_progress = [](const std::string& s) {
      std::fprintf(stderr, "compare: %s\n", s.c_str());
    };
  const backends::SuiteReport report =
      backends::CompareBackends(ref, cand, options, backends::RunCache(a.backends.Cache()));
  if (!a.markdown.empty()) WriteFileAtomically(a.markdown, report.ToMarkdown());
  std::cout << (a.json ? report.ToJson().dump(2) + "\n" : report.ToTable());
  if (!report.pass()) SetExitCode(kExitGateFailed);
}

// A trajectory file and a backend name never go together: when one argument is a file, the other
// must be one too, and is named (missing, a directory) instead of "unknown backend" for the file.
void RequireFilePartner(const std::string& file, const std::string& other) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec) || std::filesystem::is_regular_file(other, ec))
    return;
  if (std::filesystem::is_directory(other, ec))
    throw InputError(other, 0, "is a directory; expected a trajectory file like " + file);
  if (std::filesystem::exists(other, ec))
    throw InputError(other, 0, "is not a regular file; expected a trajectory file like " + file);
  throw InputError(other, 0, "no such trajectory file (and " + file + " is a file, not a backend)");
}

void RunCompare(const CompareArgs& a) {
  RequireFilePartner(a.reference, a.candidate);
  RequireFilePartner(a.candidate, a.reference);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(a.reference, ec) ||
      !std::filesystem::is_regular_file(a.candidate, ec))
    return RunBackendCompare(a);
  compare::ParityOptions options = Options(a);
  options.quiet = Flags().quiet;
  if (!a.markdown.empty()) CheckMarkdownOut(a);
  const auto reference = OpenTrajectoryArgument(a.reference);  // frame by frame
  const auto candidate = OpenTrajectoryArgument(a.candidate);
  const compare::ParityReport report =
      compare::CompareFrameSources(*reference, *candidate, options);
  if (!a.markdown.empty()) WriteFileAtomically(a.markdown, report.ToMarkdown());
  std::cout << (a.json ? report.ToJson().dump(2) + "\n" : report.ToTable());
  if (!report.pass()) SetExitCode(kExitGateFailed);
}

void SetUp(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  args->gates.reserve(compare::kGateThresholdFields.size());  // options keep pointers into it
  CLI::App* cmd = app.add_subcommand(
      "compare", "Phase 7: frame-by-frame parity of a candidate against a reference");
  cmd->footer(kGatesHelp);
  cmd->add_option("reference", args->reference, "Reference trajectory file or backend name")
      ->required();
  cmd->add_option("candidate", args->candidate, "Candidate trajectory file or backend name")
      ->required();
  AddBackendFlags(cmd, &args->backends, true);
  cmd->add_option("--scenarios", args->scenarios, "With backend names: these scenarios only")
      ->delimiter(',');
  cmd->add_option("--suite", args->suite,
                  "With backend names: parity = every scenario with a configuration (default)")
      ->check(CLI::IsMember({"parity"}));
  cmd->add_option("--reference-dir", args->reference_dir,
                  "With backend names: the scenario folders (default: the store of either "
                  "backend, else ../shared/reference)");
  cmd->add_option("--sibernetic", args->sibernetic,
                  "With backend names: Sibernetic's demos from this checkout of "
                  "openworm/sibernetic (default: $SIBERNETIC_HOME), by scenarios/sibernetic/");
  cmd->add_option("--set", args->sets, "With backend names: NAME=VALUE for {set:NAME}");
  AddTrackFlags(cmd, &args->track, "", "Tracked");
  cmd->add_option("--frames", args->frames,
                  "Reference frames to gate, e.g. 0,15,100,200 (default: all paired)");
  cmd->add_option("--scale", args->scale,
                  "Scale for the frame gate in cu (default: reference range)")
      ->check(Positive());
  for (const compare::GateThresholdField& field : compare::kGateThresholdFields) {
    args->gates.emplace_back(field.member, std::nullopt);
    cmd->add_option(field.flag, args->gates.back().second, compare::GateThresholdHelp(field))
        ->check(Positive());
  }
  cmd->add_option("--manifest", args->manifest, "Scenario manifest JSON (its track and gates)");
  cmd->add_option("--markdown", args->markdown, "Also write the report as Markdown (for a PR)");
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args] { RunCompare(*args); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
