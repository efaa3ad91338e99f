#pragma once
// Phase 1 and 3: analytic predictions made from a configuration alone, and their reconciliation
// with a measured trajectory. Every prediction states its formula, its inputs with their source
// (a configuration line or a default constant) and its result in configuration units and SI.
// JSON schema: docs/prediction.md.
#include <nlohmann/json.hpp>
#include <string>

#include "owval/engine/config.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::predict {

struct PredictOptions {
  std::string scenario;  // recorded in the prediction
  // Omit Sibernetic's 0.25 factor on springs that are not between two worm-body particles (for
  // teaching: the prediction is then off by 2x in period).
  bool omit_quarter_factor = false;
};

// Chooses the predictor from the configuration: one elastic particle on one spring → harmonic
// spring; one liquid particle and no elastic → free fall. InputError otherwise.
nlohmann::json Predict(const engine::SiberneticConfig& config,
                       const engine::PhysicsConstants& constants, const PredictOptions& options);

std::string PredictionMarkdown(const nlohmann::json& prediction);

// Measures each predicted quantity on the tracked signal of `trajectory` and compares.
// The result has per-quantity gaps, pass flags, diagnosis hints and a top-level "pass".
nlohmann::json Reconcile(const nlohmann::json& prediction, const Trajectory& trajectory);
std::string ReconcileMarkdown(const nlohmann::json& reconciliation);

}  // namespace owval::predict
