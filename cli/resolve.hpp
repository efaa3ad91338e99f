#pragma once
// Shared argument handling of the commands that run simulations.
#include <string>

#include "owval/engine/config.hpp"

namespace owval::cli {

// A scenario name (a manifest in the data directory's scenarios/) or a configuration file.
engine::SiberneticConfig ResolveConfig(const std::string& name_or_path);

// "NAME=VALUE" onto a PhysicsConstants field (elasticity_coefficient, time_step_s, ...).
void SetConstantAssignment(const std::string& assignment, engine::PhysicsConstants* constants);

}  // namespace owval::cli
