#pragma once
// The in-process evaluator: the engine itself, with named physics constants set per evaluation.
#include <string>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/sgd/targets.hpp"

namespace owval::sgd {

// Sets a PhysicsConstants field by name: engine::SetConstant, the engine's one table of
// constants (owval/engine/constants.hpp). Throws InputError for an unknown name or a value the
// table's rule refuses.
void SetConstant(engine::PhysicsConstants* constants, const std::string& name, double value);

// An engine run's tracked series, measured as each frame is produced: no frame is kept, so
// memory stays O(particles) + one number a frame whatever the run's length. InputError when
// the track names nothing in the run.
TrackedSeries RunTrackedSeries(const engine::SiberneticConfig& config,
                               const engine::RunOptions& options, const Track& track);

// Runs the engine on `config` with `base` options (one thread: finite-difference points run
// concurrently; positions only), the fitted parameters set by name; each evaluation keeps only
// its tracked series (RunTrackedSeries).
Simulator EngineSimulator(engine::SiberneticConfig config, engine::RunOptions base,
                          std::vector<Parameter> parameters);

}  // namespace owval::sgd
