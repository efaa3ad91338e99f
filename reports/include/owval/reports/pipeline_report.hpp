#pragma once
// The pipeline's two documents, assembled from what the other libraries computed: index.md /
// index.html (prediction, parity gates, fit, video, frames, checklist) and changes.md (the
// itemised substrate changes of checklist item 9).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/ci/checklist.hpp"
#include "owval/compare/parity.hpp"
#include "owval/predict/prediction.hpp"
#include "owval/reports/document.hpp"
#include "owval/sgd/fit.hpp"

namespace owval::reports {

struct FitEvidence {
  sgd::Solver solver = sgd::Solver::kLevenbergMarquardt;
  std::vector<sgd::Parameter> parameters;  // with their starting values
  sgd::FitSummary summary;
};

struct PipelineEvidence {
  std::string scenario, description;
  std::string reference_source, candidate_source;
  // name, applicable, summary of each phase, in order.
  struct PhaseLine {
    std::string name;
    bool applicable = true;
    std::string summary;
  };
  std::vector<PhaseLine> phases;
  predict::Reconciliation reconcile;  // the prediction against the reference
  compare::ParityReport parity;
  std::optional<FitEvidence> fit;  // empty: not applicable
  nlohmann::json frames;           // frames/frames.json
  ci::ChecklistReport checklist;
};

// The loss-per-iteration plot of a fit (SVG, log scale), as owval fit and the pipeline save it.
std::string ConvergencePlot(const sgd::FitSummary& summary);

Document PipelineIndex(const PipelineEvidence& evidence);
std::string ChangesMarkdown(const PipelineEvidence& evidence);

}  // namespace owval::reports
