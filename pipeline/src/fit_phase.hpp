#pragma once
// Phase 5 of the pipeline, as the scenario's manifest asks for it:
//   "fit": {"parameters": [{"name": "elasticity_coefficient", "start": 1.62e8, "log": true,
//                           "lower": 3e6, "upper": 3e10}],
//           "targets": [{"metric": "period", "weight": 1}, {"metric": "rms", "weight": 1}]}
// Target values are measured on the reference's tracked quantity (period, half_amplitude,
// equilibrium), or, for "rms", the whole tracked series of the reference (scaled by its range).
//   "fd_test": "spring_period_vs_log_k"
// the elastic kernel's response: the period scales as k^(-1/2), so dT/d(log k) = -T/2.
#include <filesystem>
#include <optional>
#include <string>

#include "owval/reports/pipeline_report.hpp"
#include "owval/scenarios/scenario.hpp"

namespace owval::pipeline {

struct FitPhase {
  const scenarios::Scenario& scenario;
  const engine::SiberneticConfig& config;
  // The report directory; reference.h5 is already in it, and the targets are measured on its
  // tracked quantity, read frame by frame.
  std::filesystem::path dir;
  bool quiet = false;
  std::string backend = "pcisph";  // the candidate's scheme: the fit runs it
};

// Fits when the manifest has "fit" and its targets can be measured on the reference; writes
// fit/history.json, fit/convergence.svg and parameters.json. Returns the outcome in words; `fit`
// stays empty when the phase does not apply (the outcome says why).
std::string RunFit(const FitPhase& phase, std::optional<reports::FitEvidence>* fit);

// Runs the manifest's "fd_test" into fd_tests.json; false (and why, in `outcome`) when the
// manifest names none. For the xpbd backend the test is `owval gradcheck all` instead, on the
// scenario's configuration (written to the report as configuration.txt), whatever the manifest
// says: the candidate's own kernels are what item 7 asks to be checked.
bool RunFiniteDifferenceTest(const FitPhase& phase, std::string* outcome);

}  // namespace owval::pipeline
