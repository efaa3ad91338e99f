#pragma once
// The in-process evaluator: the engine itself, with named physics constants set per evaluation.
#include <string>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/sgd/targets.hpp"

namespace owval::sgd {

// Sets a PhysicsConstants field by name (elasticity_coefficient, time_step_s, rest_density,
// mass_kg, simulation_scale, gravity_x|y|z, max_muscle_force, delta, surface_tension_scale,
// non_worm_body_spring_factor). Throws InputError for an unknown name.
void SetConstant(engine::PhysicsConstants* constants, const std::string& name, double value);

// Runs the engine on `config` with `base` options, the fitted parameters set by name.
Simulator EngineSimulator(engine::SiberneticConfig config, engine::RunOptions base,
                          std::vector<Parameter> parameters);

}  // namespace owval::sgd
