#include "owval/sgd/engine_simulator.hpp"

#include "owval/engine/constants.hpp"

namespace owval::sgd {

void SetConstant(engine::PhysicsConstants* c, const std::string& name, double value) {
  engine::SetConstant(c, name, value);
}

Simulator EngineSimulator(engine::SiberneticConfig config, engine::RunOptions base,
                          std::vector<Parameter> parameters, EngineRun run) {
  if (!run)
    run = [](const engine::SiberneticConfig& c, const engine::RunOptions& o) {
      return engine::Run(c, o);
    };
  base.record_fields = false;  // fits read positions only
  base.threads = 1;            // finite-difference points already run concurrently
  base.on_step = nullptr;
  for (const Parameter& p : parameters)
    engine::SetConstant(&base.constants, p.name, p.start);  // validate names now
  return [config = std::move(config), base, parameters,
          run = std::move(run)](const std::vector<double>& values) {
    engine::RunOptions options = base;
    for (std::size_t i = 0; i < parameters.size(); ++i)
      engine::SetConstant(&options.constants, parameters[i].name, values[i]);
    return run(config, options);
  };
}

}  // namespace owval::sgd
