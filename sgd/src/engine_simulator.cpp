#include "owval/sgd/engine_simulator.hpp"

#include <map>

#include "owval/base/errors.hpp"

namespace owval::sgd {

void SetConstant(engine::PhysicsConstants* c, const std::string& name, double value) {
  const std::map<std::string, double*> fields = {
      {"elasticity_coefficient", &c->elasticity_coefficient},
      {"time_step_s", &c->time_step_s},
      {"rest_density", &c->rest_density},
      {"mass_kg", &c->mass_kg},
      {"simulation_scale", &c->simulation_scale},
      {"gravity_x", &c->gravity[0]},
      {"gravity_y", &c->gravity[1]},
      {"gravity_z", &c->gravity[2]},
      {"max_muscle_force", &c->max_muscle_force},
      {"delta", &c->delta},
      {"surface_tension_scale", &c->surface_tension_scale},
      {"non_worm_body_spring_factor", &c->non_worm_body_spring_factor},
  };
  const auto it = fields.find(name);
  if (it == fields.end()) {
    std::string known;
    for (const auto& [k, v] : fields) known += (known.empty() ? "" : ", ") + k;
    throw InputError("unknown engine constant '" + name + "': expected one of " + known);
  }
  *it->second = value;
}

Simulator EngineSimulator(engine::SiberneticConfig config, engine::RunOptions base,
                          std::vector<Parameter> parameters) {
  base.record_fields = false;  // fits read positions only
  base.threads = 1;            // finite-difference points already run concurrently
  base.on_step = nullptr;
  for (const Parameter& p : parameters)
    SetConstant(&base.constants, p.name, p.start);  // validate names now
  return [config = std::move(config), base, parameters](const std::vector<double>& values) {
    engine::RunOptions options = base;
    for (std::size_t i = 0; i < parameters.size(); ++i)
      SetConstant(&options.constants, parameters[i].name, values[i]);
    return engine::Run(config, options);
  };
}

}  // namespace owval::sgd
