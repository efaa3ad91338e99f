#pragma once
// The in-process evaluator: the engine itself, with named physics constants set per evaluation.
#include <functional>
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

// How an evaluation runs the engine; the default, engine::Run, returns every frame of every
// particle. A caller that needs less (the pipeline keeps only the tracked particles) passes its
// own, so that memory stays bounded by what the targets read.
using EngineRun = std::function<Trajectory(const engine::SiberneticConfig& config,
                                           const engine::RunOptions& options)>;

// Runs the engine on `config` with `base` options (one thread: finite-difference points run
// concurrently; positions only), the fitted parameters set by name.
Simulator EngineSimulator(engine::SiberneticConfig config, engine::RunOptions base,
                          std::vector<Parameter> parameters, EngineRun run = nullptr);

}  // namespace owval::sgd
