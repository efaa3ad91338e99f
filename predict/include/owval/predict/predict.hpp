#pragma once
// Phase 1 and 3: analytic predictions made from a configuration alone, and their reconciliation
// with a measured trajectory. Every prediction states its formula, its inputs with their source
// (a configuration line or a default constant) and its result in configuration units and SI.
// Types in prediction.hpp; JSON schema: docs/prediction.md.
#include <map>
#include <optional>
#include <string>

#include "owval/engine/config.hpp"
#include "owval/predict/prediction.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::predict {

struct PredictOptions {
  std::string scenario;  // recorded in the prediction
  // harmonic_spring | free_fall | hanging_chain | hydrostatic_column | hydrostatic_tank |
  // dam_break (the last two only when named); "" = chosen from the
  // configuration's shape (see Predict).
  std::string predictor;
  // Omit Sibernetic's 0.25 factor on springs that are not between two worm-body particles (for
  // teaching: the spring prediction is then off by 2x in period).
  bool omit_quarter_factor = false;
};

// The predictor a configuration calls for: one elastic particle on one spring → harmonic_spring;
// elastic particles on springs and no liquid → hanging_chain; one liquid particle →
// free_fall; several liquid particles and no elastic → hydrostatic_column. InputError otherwise.
std::string ChoosePredictor(const engine::SiberneticConfig& config);

// Sibernetic ignores [physical parameters] (physics sheet §1), so pass PhysicsConstants{} to
// predict what the original computes.
Prediction Predict(const engine::SiberneticConfig& config,
                   const engine::PhysicsConstants& constants, const PredictOptions& options);

std::string PredictionMarkdown(const Prediction& prediction);

struct ReconcileOptions {
  std::optional<double> tolerance;           // replaces every gated quantity's tolerance
  std::map<std::string, double> tolerances;  // per quantity name (wins over `tolerance`)

  // "VALUE" (every gated quantity) or "QUANTITY=VALUE", VALUE a number >= 0 and QUANTITY not
  // empty: InputError quoting the text otherwise.
  void AddTolerance(const std::string& text);
};

// Every quantity named in options.tolerances is a gated quantity of the prediction; InputError
// naming the first that is not and listing the gated ones otherwise (a misspelt name would
// silently leave the gate at its default). Reconcile checks it first; callers may check earlier.
void CheckTolerances(const Prediction& prediction, const ReconcileOptions& options);

// Measures each predicted quantity on the tracked signal of `trajectory` (the particle or group
// centroid and axis recorded in the prediction) and compares: per-quantity gaps, pass flags,
// diagnosis hints and an overall pass. InputError when the tracked particle or group does not
// exist in the trajectory.
Reconciliation Reconcile(const Prediction& prediction, const Trajectory& trajectory,
                         const ReconcileOptions& options = {});
// The same frame by frame (issue 16: memory O(particles) and a few numbers a frame), with the
// same values: each measure is a pass over the frames in time order (pressures read with them).
Reconciliation Reconcile(const Prediction& prediction, FrameSource& frames,
                         const ReconcileOptions& options = {});
std::string ReconcileMarkdown(const Reconciliation& reconciliation);

}  // namespace owval::predict
