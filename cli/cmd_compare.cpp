// owval compare REF CAND: the parity report a backend port must pass (exit 1 when a gate fails).
#include <cstdio>
#include <iostream>
#include <sstream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/compare/parity.hpp"
#include "owval/trajectory/formats.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct CompareArgs {
  std::string reference, candidate;
  std::optional<std::size_t> particle;
  std::string group;
  std::string axis = "y";
  std::string frames;
  std::optional<double> scale, threshold;
  std::string manifest;
  std::string markdown;
  bool json = false;
};

// Scenario manifests may carry gate thresholds: {"gates": {"frame_threshold": 0.05,
// "period_gap_threshold": 0.02, "amplitude_gap_threshold": 0.05}, "track": {"particle": 0,
// "group": "", "axis": "y"}}. Command-line flags override them.
void ApplyManifest(const std::string& path, compare::ParityOptions* o) {
  const nlohmann::json m = [&] {
    try {
      return nlohmann::json::parse(ReadWholeFile(path));
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError(path, 0, std::string("not valid JSON: ") + e.what());
    }
  }();
  const nlohmann::json gates = m.value("gates", nlohmann::json::object());
  o->frame_threshold = gates.value("frame_threshold", o->frame_threshold);
  o->period_gap_threshold = gates.value("period_gap_threshold", o->period_gap_threshold);
  o->amplitude_gap_threshold = gates.value("amplitude_gap_threshold", o->amplitude_gap_threshold);
  const nlohmann::json track = m.value("track", nlohmann::json::object());
  o->particle = track.value("particle", o->particle);
  o->group = track.value("group", o->group);
  if (track.contains("axis")) o->axis = ParseAxis(track["axis"].get<std::string>());
}

void RunCompare(const CompareArgs& a) {
  compare::ParityOptions options;
  if (!a.manifest.empty()) ApplyManifest(a.manifest, &options);
  if (a.particle) options.particle = *a.particle;
  if (!a.group.empty()) options.group = a.group;
  options.axis = ParseAxis(a.axis);
  if (!a.frames.empty()) options.sample_frames = ParseIndexList(a.frames, "--frames");
  options.scale = a.scale;
  if (a.threshold) options.frame_threshold = *a.threshold;
  const Trajectory reference = ReadTrajectoryArgument(a.reference);
  const Trajectory candidate = ReadTrajectoryArgument(a.candidate);
  const compare::ParityReport report = compare::CompareTrajectories(reference, candidate, options);
  if (!a.markdown.empty()) WriteFileAtomically(a.markdown, report.ToMarkdown());
  if (a.json) {
    std::cout << report.ToJson().dump(2) << "\n";
  } else {
    std::cout << report.ToTable();
  }
  if (!report.pass()) SetExitCode(kExitGateFailed);
}

void SetUp(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare", "Phase 7: frame-by-frame parity of a candidate against a reference");
  cmd->add_option("reference", args->reference, "Reference trajectory")->required();
  cmd->add_option("candidate", args->candidate, "Candidate trajectory")->required();
  auto* particle = cmd->add_option("--particle", args->particle, "Tracked particle (default 0)");
  cmd->add_option("--group", args->group, "Track a group centroid: elastic, liquid, all")
      ->excludes(particle)
      ->check(CLI::IsMember({"elastic", "liquid", "all"}));
  cmd->add_option("--axis", args->axis, "x, y or z")->check(CLI::IsMember({"x", "y", "z"}));
  cmd->add_option("--frames", args->frames,
                  "Reference frames to gate, e.g. 0,15,100,200 (default: all)");
  cmd->add_option("--scale", args->scale, "Scale for |delta| in cu (default: reference range)");
  cmd->add_option("--threshold", args->threshold,
                  "Frame gate: |delta|/scale must stay below (default 0.05)");
  cmd->add_option("--manifest", args->manifest, "Scenario manifest JSON with gate thresholds");
  cmd->add_option("--markdown", args->markdown, "Also write the report as Markdown (for a PR)");
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args] { RunCompare(*args); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
