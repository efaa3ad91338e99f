#include "owval/backends/commands.hpp"

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/index_list.hpp"
#include "owval/base/one_line.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::backends {
namespace {
namespace fs = std::filesystem;

// A trajectory file and a backend name never go together: when one argument is a file, the other
// must be one too, and is named (missing, a directory) instead of "unknown backend" for the file.
void RequireFilePartner(const std::string& file, const std::string& other) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || fs::is_regular_file(other, ec)) return;
  if (fs::is_directory(other, ec))
    throw InputError(other, 0, "is a directory; expected a trajectory file like " + file);
  if (fs::exists(other, ec))
    throw InputError(other, 0, "is not a regular file; expected a trajectory file like " + file);
  throw InputError(other, 0, "no such trajectory file (and " + file + " is a file, not a backend)");
}

// `registry`: the backends file a comparison of backend names reads ("" for two files).
void CheckMarkdownOut(const CompareRequest& r, const fs::path& registry = {}) {
  if (r.markdown.empty()) return;
  CheckOutputPath(r.markdown);
  CheckOutputIsNotAnInput(r.markdown, {r.reference, r.candidate, r.manifest, registry});
}

compare::ParityOptions FileParityOptions(const CompareRequest& r) {
  compare::ParityOptions o;
  if (!r.manifest.empty()) scenarios::ApplyManifestFile(r.manifest, &o);
  o.track = r.track.Over(o.track);
  if (!r.frames.empty()) o.sample_frames = ParseIndexList(r.frames, "--frames");
  o.scale = r.scale;
  for (std::size_t i = 0; i < r.thresholds.size() && i < compare::kGateThresholdFields.size(); ++i)
    if (r.thresholds[i])
      o.gates.*compare::kGateThresholdFields[i].member = {*r.thresholds[i],
                                                          compare::ThresholdSource::kFlag};
  o.quiet = r.reading.quiet;
  return o;
}

// What compare::CompareFrameSources refuses, said of the files: a reference of fewer than two
// frames, a candidate of none, a different number of particles.
void RequireComparableFiles(const CompareRequest& r, const FrameSource& reference,
                            const FrameSource& candidate) {
  RequireFrames(reference, r.reference, 2);  // a run over time to compare with
  RequireFrames(candidate, r.candidate, 1);
  if (candidate.particle_count() != reference.particle_count())
    throw InputError(r.candidate, 0,
                     std::to_string(candidate.particle_count()) +
                         " particles; expected the reference's " +
                         std::to_string(reference.particle_count()));
}

// A flag of the other form of compare was ignored: `compare A.txt B.txt --scenarios demo1` and
// `compare opencl owval --threshold 0.01` said nothing of it (the suite takes each
// scenario's manifest gates). The first such flag, or "".
std::string SuiteOnlyFlagGiven(const CompareRequest& r) {
  if (!r.scenarios.names.empty()) return "--scenarios";
  if (!r.scenarios.sibernetic.empty()) return "--sibernetic";
  if (!r.scenarios.reference_dir.empty()) return "--reference-dir";
  if (!r.sets.empty()) return "--set";
  if (!r.backends.file.empty()) return "--backends";
  if (!r.backends.cache.directory.empty()) return "--cache";
  if (!r.backends.cache.enabled) return "--no-cache";
  return "";
}
std::string FilesOnlyFlagGiven(const CompareRequest& r) {
  if (!r.manifest.empty()) return "--manifest";
  if (r.track.given() || r.track.axis) return "the tracked quantity (--particle, --group, --axis)";
  if (!r.frames.empty()) return "--frames";
  if (r.scale) return "--scale";
  for (std::size_t i = 0; i < r.thresholds.size() && i < compare::kGateThresholdFields.size(); ++i)
    if (r.thresholds[i]) return compare::kGateThresholdFields[i].flag;
  return "";
}

SuiteReport CompareBackendNames(const CompareRequest& r) {
  if (const std::string flag = FilesOnlyFlagGiven(r); !flag.empty())
    throw InputError("compare " + r.reference + " " + r.candidate + ": " + flag +
                     " applies to two trajectory files; with backend names each scenario's "
                     "manifest sets the track and gates");
  CheckMarkdownOut(r, RegistryFile(RegistryOptionsFromEnvironment(r.backends.file)));
  for (const std::string& arg : {r.reference, r.candidate}) {
    std::error_code ec;
    if (arg.find('/') != std::string::npos && !fs::is_regular_file(arg, ec))
      throw InputError(arg, 0, "no such trajectory file (and not a backend name)");
  }
  const Registry registry = r.backends.Load();
  const Backend& reference = registry.Find(r.reference);
  const Backend& candidate = registry.Find(r.candidate);
  SuiteOptions options;
  SelectScenarios(reference, candidate, r.scenarios, &options);
  options.sets = ParseSets(r.sets);
  options.on_progress = r.on_progress;
  return CompareBackends(reference, candidate, options, RunCache(r.backends.cache));
}

// Two files without --manifest, the reference a store folder's recorded run (meta.json beside
// it): `compare` by backend names judges that run by its scenario's manifest, these files by
// DD001's defaults on particle 0, and owval with gravity 4% off passed test_gravity so. Said,
// not applied: the file form's judgement stays what its flags say. "" when there is nothing to
// say (a meta.json that cannot be read is not this command's input).
std::string StoreManifestNote(const CompareRequest& r) {
  std::error_code ec;  // absolute: "position_buffer.txt" in the folder itself has a folder name
  const fs::path directory = fs::absolute(r.reference, ec).lexically_normal().parent_path();
  if (!r.manifest.empty() || !fs::is_regular_file(directory / "meta.json", ec) ||
      !fs::equivalent(RecordedTrajectory(directory), r.reference, ec))
    return "";
  try {
    const fs::path manifest =
        ScenarioManifest(ReadScenario(directory), StoreManifestDirectories(r.scenarios.data_dir));
    if (manifest.empty()) return "";
    return OneLine("the reference is the store's run of " + directory.filename().string() +
                   ", which `compare` by backend names judges by its manifest's track and gates: "
                   "add --manifest " +
                   manifest.string() + " to judge these files so");
  } catch (const InputError&) {
    return "";
  }
}

}  // namespace

std::map<std::string, std::string> ParseSets(const std::vector<std::string>& sets) {
  std::map<std::string, std::string> out;
  for (const std::string& s : sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--set " + s + ": expected NAME=VALUE");
    // Given twice, the last one won silently (as --set's of run and predict did).
    if (!out.emplace(s.substr(0, eq), s.substr(eq + 1)).second)
      throw InputError("--set " + s + ": " + s.substr(0, eq) + " is given twice");
  }
  return out;
}

Registry BackendSelection::Load() const {
  return LoadRegistry(RegistryOptionsFromEnvironment(file));
}

bool CompareOutcome::pass() const { return files ? files->pass() : suite->pass(); }
nlohmann::json CompareOutcome::ToJson() const { return files ? files->ToJson() : suite->ToJson(); }
std::string CompareOutcome::ToTable() const { return files ? files->ToTable() : suite->ToTable(); }
std::string CompareOutcome::ToMarkdown() const {
  return files ? files->ToMarkdown() : suite->ToMarkdown();
}

CompareOutcome CompareNamed(const CompareRequest& r) {
  RequireFilePartner(r.reference, r.candidate);
  RequireFilePartner(r.candidate, r.reference);
  CompareOutcome outcome;
  std::error_code ec;
  if (!fs::is_regular_file(r.reference, ec) || !fs::is_regular_file(r.candidate, ec)) {
    outcome.suite = CompareBackendNames(r);
  } else {
    if (const std::string flag = SuiteOnlyFlagGiven(r); !flag.empty())
      throw InputError("compare: " + flag +
                       " applies to two backend names; the reference and candidate given are "
                       "trajectory files");
    const compare::ParityOptions options = FileParityOptions(r);
    CheckMarkdownOut(r);
    const auto reference = OpenFrameSource(r.reference, r.reading);  // frame by frame
    const auto candidate = OpenFrameSource(r.candidate, r.reading);
    RequireComparableFiles(r, *reference, *candidate);
    outcome.files = compare::CompareFrameSources(*reference, *candidate, options);
    if (const std::string note = StoreManifestNote(r); !note.empty()) outcome.notes.push_back(note);
  }
  if (!r.markdown.empty()) WriteFileAtomically(r.markdown, outcome.ToMarkdown());
  return outcome;
}

BenchReport BenchNamed(const BenchRequest& r) {
  if (!r.json.empty()) CheckOutputPath(r.json);
  if (!r.markdown.empty()) CheckOutputPath(r.markdown);
  const Registry registry = r.backends.Load();
  std::vector<Backend> chosen;
  for (const std::string& name : r.names) chosen.push_back(registry.Find(name));
  BenchOptions options = r.options;
  options.scenario = FindScenarios(r.reference_dir, {r.scenario}).front();
  std::vector<fs::path> inputs = {r.backends.file};
  for (const auto& entry : fs::directory_iterator(options.scenario.directory))
    inputs.push_back(entry.path());
  for (const std::string& out : {r.json, r.markdown})
    if (!out.empty()) CheckOutputIsNotAnInput(out, inputs);
  if (r.time_s > 0) options.scenario.time_s = r.time_s;
  options.sets = ParseSets(r.sets);
  const BenchReport report = BenchBackends(chosen, options);
  if (!r.markdown.empty()) WriteFileAtomically(r.markdown, report.ToMarkdown());
  if (!r.json.empty()) WriteFileAtomically(r.json, report.ToJson().dump(2) + "\n");
  return report;
}

}  // namespace owval::backends
