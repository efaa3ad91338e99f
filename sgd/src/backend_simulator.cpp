#include "owval/sgd/backend_simulator.hpp"

#include "owval/backends/cache.hpp"
#include "owval/backends/runner.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"

namespace owval::sgd {
namespace fs = std::filesystem;

void CheckFittableBackend(const backends::Backend& backend,
                          const std::vector<std::string>& parameter_names) {
  const std::string where = "backend " + backend.name + " (" + backend.defined_in + ")";
  if (backend.kind != backends::BackendKind::kCommand)
    throw InputError(where + ": a " + backends::KindName(backend.kind) +
                     " backend; a fit runs a command backend (the engine's own schemes: "
                     "owval fit --backend)");
  for (const std::string& name : parameter_names)
    if (backend.command.find("{set:" + name + "}") == std::string::npos)
      throw InputError(where + ": its command has no {set:" + name +
                       "}, so the fitted parameter would never reach it");
}

TrackedSeries RunBackendTrackedSeries(const backends::Backend& backend, const BackendRun& run,
                                      const std::vector<std::string>& parameter_names,
                                      const std::vector<double>& values, const Track& track) {
  backends::Backend no_fallback = backend;
  no_fallback.store.clear();  // a recorded run would answer every parameter the same
  backends::RunRequest request;
  request.scenario.name = "fit";
  request.scenario.configuration = fs::absolute(run.configuration);
  request.scenario.time_s = run.duration_s;
  request.scenario.time_step_s = run.time_step_s;
  request.scenario.log_step = run.log_step;
  for (std::size_t i = 0; i < parameter_names.size(); ++i)
    request.sets[parameter_names[i]] = FormatNumber(values[i], 17);
  const backends::RunCache uncached({"", false});  // each run in its own temporary directory
  const backends::RunOutcome outcome = backends::ObtainRun(no_fallback, request, uncached);
  return ReadTrackedSeries(*outcome.Frames(), track);
}

Simulator BackendSimulator(backends::Backend backend, BackendRun run,
                           std::vector<Parameter> parameters) {
  std::vector<std::string> names;
  for (const Parameter& p : parameters) names.push_back(p.name);
  CheckFittableBackend(backend, names);
  return [backend = std::move(backend), run = std::move(run), names](
             const std::vector<double>& values, const Track& track) {
    return RunBackendTrackedSeries(backend, run, names, values, track);
  };
}

nlohmann::json BackendSimulationJson(const backends::Backend& backend, const BackendRun& run,
                                     const nlohmann::json& configuration) {
  return {{"kind", "backend"},
          {"name", backend.name},
          {"command", backend.command},
          {"configuration", configuration},
          {"duration_s", run.duration_s},
          {"time_step_s", run.time_step_s},
          {"log_step", run.log_step}};
}

}  // namespace owval::sgd
