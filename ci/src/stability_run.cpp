#include "owval/ci/stability_run.hpp"

#include <cmath>
#include <memory>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/compare/stability.hpp"
#include "owval/engine/long_run.hpp"

namespace owval::ci {

GateReport StreamedStability(const engine::SiberneticConfig& config,
                             const StreamedStabilityOptions& o) {
  engine::RunOptions run;
  run.duration_s = o.duration_s;
  run.log_step = o.log_step;
  run.backend = o.backend;
  run.dump_dir = o.out;
  run.on_step = o.on_step;
  engine::LongRunOptions files;
  files.out = o.out;
  std::unique_ptr<compare::StabilityMonitor> monitor;
  files.on_begin = [&](const Trajectory& t) {
    monitor = std::make_unique<compare::StabilityMonitor>(t.box, t.type,
                                                          compare::LongRunStabilityOptions());
  };
  files.on_frame = [&](const engine::FrameView& f) {
    monitor->Observe(f.time_s, f.positions.data(),
                     f.velocities.empty() ? nullptr : f.velocities.data(),
                     f.density.empty() ? nullptr : f.density.data());
  };
  std::ostringstream name;
  name << "stability over " << o.duration_s << " s (" << config.source << ", streamed)";
  GateResult gate{name.str(), false, ""};
  try {
    const engine::RunSummary s = engine::RunToFiles(config, run, files);
    const compare::StabilityReport& r = monitor->report();
    gate.pass = r.pass();
    gate.detail = std::to_string(s.steps) + " steps, " + r.ToJson().dump();
  } catch (const SimulationError& e) {
    gate.detail = e.what();
  }
  return GateReport{{gate}};
}

double ParseDuration(const std::string& text, const std::string& flag) {
  std::size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = text.substr(used);
  while (!unit.empty() && unit.front() == ' ') unit.erase(0, 1);
  const double scale = unit == "ms" ? 1e-3 : (unit.empty() || unit == "s") ? 1 : NAN;
  if (used == 0 || !(value * scale > 0) || !std::isfinite(value * scale))
    throw InputError(flag + " '" + text + "': expected a positive duration such as 10s or 500ms");
  return value * scale;
}

}  // namespace owval::ci
