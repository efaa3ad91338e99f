#include "owval/pipeline/pipeline.hpp"

#include <algorithm>
#include <cmath>

#include "fit_phase.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/temporary_directory.hpp"
#include "owval/engine/solver.hpp"
#include "owval/predict/predict.hpp"
#include "owval/render/render.hpp"
#include "owval/reports/pipeline_report.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "trajectory_files.hpp"

namespace owval::pipeline {
namespace fs = std::filesystem;
namespace {

// Everything the phases share: the scenario, the directory and what each phase produced for the
// report. The trajectories are reference.h5 and candidate.h5 in the directory, written as they
// are produced and read frame by frame (memory O(particles), whatever the run's length).
struct Context {
  Context(const Options& o, Summary* s) : options(o), dir(o.out_dir), summary(s) {}
  const Options& options;
  scenarios::Scenario scenario;
  engine::SiberneticConfig config;
  fs::path dir;
  // The scenario's own reference for the checklist: the bundled file, or reference.h5 when the
  // engine made it here.
  fs::path scenario_reference;
  predict::Prediction prediction;
  reports::PipelineEvidence evidence;
  Summary* summary;
};

void WriteJson(const fs::path& path, const nlohmann::json& j) {
  WriteFileAtomically(path, j.dump(2) + "\n");
}

void Done(Context& c, const std::string& name, bool applicable, const std::string& outcome) {
  c.summary->phases.push_back({name, applicable, outcome});
  c.evidence.phases.push_back({name, applicable, outcome});
  if (c.options.on_phase)
    c.options.on_phase(name + ": " + (applicable ? "" : "not applicable: ") + outcome);
}

engine::RunOptions RunOptionsFor(const scenarios::Scenario& scenario, engine::Integrator integrator,
                                 const std::string& backend = "pcisph") {
  engine::RunOptions o;
  o.duration_s = scenario.duration_s;
  o.log_step = scenario.log_step;
  o.integrator = integrator;
  o.backend = backend;
  return o;
}

predict::Prediction PredictionOf(const scenarios::Scenario& scenario,
                                 const engine::SiberneticConfig& config) {
  predict::PredictOptions o;
  o.scenario = scenario.name;
  o.predictor = scenario.predictor;
  return predict::Predict(config, engine::PhysicsConstants{}, o);
}

void Predict(Context& c) {
  c.prediction = PredictionOf(c.scenario, c.config);
  WriteJson(c.dir / "prediction.json", c.prediction.ToJson());
  Done(c, "1 predict", true,
       std::to_string(c.prediction.predictions.size()) + " quantities in prediction.json");
}

std::string BundledSource(const scenarios::Scenario& scenario) {
  return "bundled Sibernetic OpenCL run (" + scenario.reference.filename().string() + ")";
}
const char* const kEngineReferenceSource =
    "owval engine, PCISPH, semi-implicit Euler (reproduces Sibernetic's OpenCL run)";

engine::RunOptions ReferenceRunOptions(const scenarios::Scenario& scenario) {
  return RunOptionsFor(scenario, engine::Integrator::kSemiImplicitEuler);
}

// reference.h5, streamed from the bundled file or from the engine as it runs.
void Reference(Context& c) {
  const fs::path reference = c.dir / "reference.h5";
  if (!c.scenario.reference.empty()) {
    TextReadOptions read;
    read.quiet = c.options.quiet;
    CopyTrajectoryFile(c.scenario.reference, reference, read);
    c.scenario_reference = c.scenario.reference;
    c.evidence.reference_source = BundledSource(c.scenario);
  } else {
    RunIntoFile(c.config, ReferenceRunOptions(c.scenario), reference);
    c.scenario_reference = reference;
    c.evidence.reference_source = kEngineReferenceSource;
  }
  Done(c, "2 reference", true, "reference.h5 from " + c.evidence.reference_source);
}

void Inspect(Context& c) {
  c.evidence.reconcile = predict::Reconcile(c.prediction, *OpenQuietly(c.dir / "reference.h5"));
  WriteJson(c.dir / "reconcile.json", c.evidence.reconcile.ToJson());
  WriteFileAtomically(c.dir / "reconcile.md", predict::ReconcileMarkdown(c.evidence.reconcile));
  c.summary->prediction_holds = c.evidence.reconcile.pass;
  Done(c, "3 inspect", true,
       c.summary->prediction_holds ? "the prediction holds on the reference"
                                   : "a predicted quantity misses the reference (reconcile.md)");
}

// candidate.h5, streamed from the given file or from the engine as it runs.
void Candidate(Context& c) {
  const fs::path candidate = c.dir / "candidate.h5";
  if (!c.options.candidate.empty()) {
    c.evidence.candidate_source = "given trajectory " + c.options.candidate.string();
    TextReadOptions read;
    read.quiet = c.options.quiet;
    CopyTrajectoryFile(c.options.candidate, candidate, read);
  } else {
    const bool leapfrog = c.options.integrator == engine::Integrator::kLeapfrog;
    const std::string backend = engine::CanonicalBackend(c.options.backend);
    RunIntoFile(c.config, RunOptionsFor(c.scenario, c.options.integrator, backend), candidate);
    c.evidence.candidate_source =
        backend == "pcisph" ? std::string("owval engine on the CPU, PCISPH, ") +
                                  (leapfrog ? "leapfrog" : "semi-implicit Euler") + " integrator"
                            : "owval engine on the CPU, backend " + backend;
  }
  Done(c, "4 candidate", true, "candidate.h5 from " + c.evidence.candidate_source);
}

std::vector<std::size_t> SampleFrames(const Context& c, std::size_t reference_frames) {
  std::vector<std::size_t> at;
  for (std::size_t f : c.scenario.sample_frames)
    at.push_back(std::min<std::size_t>(f, reference_frames - 1));
  at.erase(std::unique(at.begin(), at.end()), at.end());
  return at;
}

void Render(Context& c) {
  render::RenderOptions o;
  o.boundary = render::BoundaryMode::kTranslucent;
  o.max_frames = c.options.max_video_frames;
  o.title = c.scenario.name;
  o.tracking = c.scenario.track;
  o.quiet = c.options.quiet;
  const auto reference = OpenQuietly(c.dir / "reference.h5");
  const auto candidate = OpenQuietly(c.dir / "candidate.h5");
  const render::VideoSummary video =
      render::RenderSideBySide(*reference, *candidate, o, c.dir / "sxs.mp4");
  c.evidence.frames = render::RenderFrames(
      *reference, *candidate, SampleFrames(c, reference->frame_count()), o, c.dir / "frames");
  Done(c, "6 render", true,
       "sxs.mp4 (" + std::to_string(video.frames) + " frames) and " +
           std::to_string(c.evidence.frames["frames"].size()) + " labelled frames");
}

void Compare(Context& c) {
  compare::ParityOptions o;
  o.track = c.scenario.track;
  o.gates = c.scenario.gates;
  c.summary->parity = compare::CompareFrameSources(*OpenQuietly(c.dir / "reference.h5"),
                                                   *OpenQuietly(c.dir / "candidate.h5"), o);
  c.evidence.parity = c.summary->parity;
  WriteJson(c.dir / "parity.json", c.summary->parity.ToJson());
  WriteFileAtomically(c.dir / "parity.md", c.summary->parity.ToMarkdown());
  Done(c, "7 compare", true,
       c.summary->parity.pass() ? "every applicable parity gate passes"
                                : "FAIL: " + c.summary->parity.FailedGates());
}

void Checklist(Context& c) {
  ci::ChecklistOptions o;
  o.gates = c.scenario.gates;
  o.track = c.scenario.track;
  o.caller_reference = c.scenario_reference;
  o.caller_reference_source = c.scenario.name + "'s " + c.evidence.reference_source;
  o.scenario_prediction = c.prediction;
  c.summary->checklist = ci::RunChecklist(c.dir, o);
  c.summary->checklist.directory = c.options.out_dir;  // where it lands, not the temporary
  c.evidence.checklist = c.summary->checklist;
  WriteFileAtomically(c.dir / "checklist.md", c.summary->checklist.ToMarkdown());
  WriteJson(c.dir / "checklist.json", c.summary->checklist.ToJson());
  Done(c, "8 checklist", true, ci::VerdictName(c.summary->checklist.verdict));
}

void WriteDocuments(Context& c) {
  // The checklist bot's `--scenario` (.github/workflows/checklist.yml reads it): the reference
  // the pull request is judged against is this built-in scenario's, not the directory's.
  WriteFileAtomically(c.dir / "scenario", c.scenario.name + "\n");
  const reports::Document index = reports::PipelineIndex(c.evidence);
  WriteFileAtomically(c.dir / "index.md", index.Markdown());
  WriteFileAtomically(c.dir / "index.html", index.Html());
  c.summary->index_html = c.dir / "index.html";
}

// What can be known before any work: the scenario, the directory, the candidate file.
void Prepare(Context& c) {
  c.scenario = scenarios::LoadScenario(c.options.scenario, c.options.data_dir);
  c.config = scenarios::GenerateConfig(c.scenario);
  c.evidence.scenario = c.scenario.name;
  c.evidence.description = c.scenario.description;
  CheckOutputPath(c.options.out_dir / "index.html");
  const std::string backend = engine::CanonicalBackend(c.options.backend);
  if (backend != "pcisph" && c.options.integrator != engine::Integrator::kSemiImplicitEuler)
    throw InputError("pipeline: backend " + backend +
                     " takes no integrator (leapfrog is PCISPH's)");
  if (!c.options.candidate.empty()) {  // its header and every frame checked, one at a time
    const auto candidate = OpenQuietly(c.options.candidate);
    if (candidate->particle_count() != c.config.particle_count())
      throw InputError(c.options.candidate.string(), 0,
                       "has " + std::to_string(candidate->particle_count()) +
                           " particles; scenario " + c.scenario.name + " has " +
                           std::to_string(c.config.particle_count()));
    for (std::size_t f = 0; f < candidate->frame_count(); ++f) candidate->Frame(f);
  }
}

// A report directory owval may replace: one it marked, or one with a whole report's layout
// (index.html, checklist.json and prediction.json), as owval wrote reports before the marker.
bool IsOwvalReport(const fs::path& existing) {
  std::error_code error;
  if (fs::is_regular_file(OwvalDirectoryMarker(existing), error)) return true;
  for (const char* name : {"index.html", "checklist.json", "prediction.json"})
    if (!fs::is_regular_file(existing / name, error)) return false;
  return true;
}

}  // namespace

ScenarioReference MakeScenarioReference(const std::string& name, const fs::path& data_dir) {
  const scenarios::Scenario scenario = scenarios::LoadScenario(name, data_dir);
  if (!scenario.reference.empty()) return {scenario.reference, BundledSource(scenario), nullptr};
  // The engine's run streamed into a scratch directory, removed with the last copy of the result
  // (or by SIGINT/SIGTERM: a Ctrl-C during the run left it behind).
  const auto directory = std::make_shared<TemporaryDirectory>("owval-reference");
  const std::shared_ptr<const fs::path> owner(directory, &directory->path());
  engine::RunOptions positions_only = ReferenceRunOptions(scenario);
  positions_only.record_fields = false;  // item 2 compares positions
  RunIntoFile(scenarios::GenerateConfig(scenario), positions_only, *owner / "reference.h5");
  return {*owner / "reference.h5", kEngineReferenceSource, owner};
}

predict::Prediction MakeScenarioPrediction(const std::string& name, const fs::path& data_dir) {
  const scenarios::Scenario scenario = scenarios::LoadScenario(name, data_dir);
  return PredictionOf(scenario, scenarios::GenerateConfig(scenario));
}

int Summary::exit_code() const { return checklist.exit_code() != 0 || !parity.pass() ? 1 : 0; }

std::string Summary::BriefReport() const {
  std::string s;
  for (const Phase& p : phases)
    s += p.name + ": " + (p.applicable ? "" : "not applicable: ") + p.summary + "\n";
  return s;
}

nlohmann::json Summary::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const Phase& p : phases)
    list.push_back({{"name", p.name}, {"applicable", p.applicable}, {"summary", p.summary}});
  return {{"report", index_html.string()},
          {"exit_code", exit_code()},
          {"prediction_holds", prediction_holds},
          {"phases", list},
          {"parity", parity.ToJson()},
          {"checklist", checklist.ToJson()}};
}

void Run(const Options& given, Summary* summary) {
  Options options = given;
  if (options.out_dir.empty()) options.out_dir = fs::path("reports") / options.scenario;
  *summary = Summary{};
  Context c(options, summary);
  Prepare(c);
  // Every artifact lands in a temporary sibling; the report replaces an older one only whole.
  AtomicDirectory report(options.out_dir, IsOwvalReport);
  c.dir = report.temporary_path();
  MarkOwvalDirectory(c.dir);
  Predict(c);
  Reference(c);
  Inspect(c);
  Candidate(c);
  FitPhase fit{c.scenario, c.config, c.dir, options.quiet, options.backend};
  const std::string fit_outcome = RunFit(fit, &c.evidence.fit);
  Done(c, "5 fit", c.evidence.fit.has_value(), fit_outcome);
  std::string fd_outcome;
  const bool fd_applies = RunFiniteDifferenceTest(fit, &fd_outcome);
  Done(c, "5 finite differences", fd_applies, fd_outcome);
  Render(c);
  Compare(c);
  WriteFileAtomically(c.dir / "changes.md", reports::ChangesMarkdown(c.evidence));
  Checklist(c);
  WriteDocuments(c);
  report.Commit();
  c.summary->index_html = options.out_dir / "index.html";
}

}  // namespace owval::pipeline
