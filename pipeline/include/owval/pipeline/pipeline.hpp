#pragma once
// The 8-phase workflow on one built-in scenario, into one report directory whose layout is the PR
// checklist's (docs/checklist.md): predict -> reference -> inspect -> candidate -> fit -> render
// -> compare -> checklist. Everything scenario-specific comes from its manifest
// (scenarios/manifests/NAME.json): the tracked quantity, the predictor, the fitted parameters and
// their targets, the finite-difference test, the sampled frames and the gates. A phase the
// manifest does not call for (nothing to fit, no kernel to test) is reported as not applicable.
//
//   pipeline::Options options;
//   options.scenario = "one_sprig";
//   options.out_dir = "reports/one_sprig";
//   pipeline::Summary summary;
//   pipeline::Run(options, &summary);
//   std::cout << summary.BriefReport();
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "owval/ci/checklist.hpp"
#include "owval/compare/parity.hpp"
#include "owval/engine/run.hpp"
#include "owval/predict/prediction.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::pipeline {

struct Options {
  std::string scenario;             // a built-in scenario name
  std::filesystem::path data_dir;   // holds scenarios/manifests and bundled references
  std::filesystem::path out_dir;    // the report directory (created); empty: reports/SCENARIO
  std::filesystem::path candidate;  // a trajectory file; empty: an owval engine run
  engine::Integrator integrator = engine::Integrator::kSemiImplicitEuler;  // of the engine run
  // The candidate's scheme (engine::KnownBackends()): the engine run's, or the one that made the
  // given candidate file. For "xpbd", the differentiable substrate,
  // phase 5 fits the XPBD run and its finite-difference test is `owval gradcheck all` (every
  // backward kernel, one step, and a multi-step reverse pass on the scenario's configuration)
  // into fd_tests.json, the checklist's item 7.
  std::string backend = "pcisph";
  std::size_t max_video_frames = 300;  // sxs.mp4 frames, evenly spaced
  bool quiet = false;                  // no progress bars
  // One line per finished phase ("5 fit: ..."); may be empty.
  std::function<void(const std::string&)> on_phase;
};

struct Phase {
  std::string name;        // "1 predict", ..., "8 checklist"
  bool applicable = true;  // false: the scenario does not call for it (summary says why)
  std::string summary;     // what it produced or measured
};

struct Summary {
  std::vector<Phase> phases;
  bool prediction_holds = false;  // reconciliation of the prediction with the reference
  compare::ParityReport parity;
  ci::ChecklistReport checklist;
  std::filesystem::path index_html;

  // 0 when the checklist is ready (or incomplete but not blocking) and parity passes, else 1.
  int exit_code() const;
  std::string BriefReport() const;
  // {"report": index.html's path, "exit_code", "prediction_holds", "phases": [{"name",
  // "applicable", "summary"}], "parity": ParityReport::ToJson, "checklist":
  // ChecklistReport::ToJson}: what `owval pipeline --json` prints.
  nlohmann::json ToJson() const;
};

// Runs every phase. InputError for an unknown scenario or unusable candidate, before anything is
// written when it can be known then.
void Run(const Options& options, Summary* summary);

// A built-in scenario's reference, as phase 2 makes it: the bundled Sibernetic OpenCL run its
// manifest names, else owval's PCISPH engine (semi-implicit Euler, which reproduces Sibernetic's
// run) over the manifest's duration and log step, streamed into a temporary HDF5 file (positions
// only) that is removed when the last copy of the ScenarioReference goes. The checklist holds a
// directory's reference.h5 to it frame by frame (`owval checklist DIR --scenario NAME`), so
// memory stays O(particles) whatever the scenario's length.
struct ScenarioReference {
  std::filesystem::path file;  // a trajectory file, to read with OpenFrameSource
  std::string source;          // "bundled Sibernetic OpenCL run (position_buffer.txt)"
  std::shared_ptr<const std::filesystem::path> scratch;  // the engine run's directory, or null
};
ScenarioReference MakeScenarioReference(const std::string& scenario,
                                        const std::filesystem::path& data_dir);

// A built-in scenario's prediction, as phase 1 makes it (its predictor on its configuration,
// Sibernetic's constants).
predict::Prediction MakeScenarioPrediction(const std::string& scenario,
                                           const std::filesystem::path& data_dir);

}  // namespace owval::pipeline
