#include "owval/ci/stability_run.hpp"

#include <cmath>
#include <memory>
#include <sstream>
#include <string_view>

#include "owval/base/errors.hpp"
#include "owval/base/number_text.hpp"
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
    gate.measured = r.ToJson();
    gate.measured["steps"] = s.steps;
    gate.detail = std::to_string(s.steps) + " steps, " + r.ToJson().dump();
  } catch (const SimulationError& e) {
    gate.detail = e.what();
  }
  return GateReport{{gate}};
}

// "10s", "500ms", "10 s" or "10": the number by ParseDecimal (std::stod took "0x10s" as 16 s).
double ParseDuration(const std::string& text, const std::string& flag) {
  std::string_view number(text);
  double scale = 1;
  if (number.ends_with("ms")) {
    number.remove_suffix(2);
    scale = 1e-3;
  } else if (number.ends_with("s")) {
    number.remove_suffix(1);
  }
  while (number.ends_with(' ')) number.remove_suffix(1);
  const std::optional<double> value = ParseDecimal(number);
  if (!value || !(*value * scale > 0))
    throw InputError(flag + " '" + text + "': expected a positive duration such as 10s or 500ms");
  return *value * scale;
}

}  // namespace owval::ci
