#pragma once
// DD001's long-run stability gate (issue 16): a scenario run for a stated simulated time with the
// stability checks applied to the stream, frame by frame, as the frames are written (NaN,
// escapes, kinetic blow-up, density 700-1300 kg/m^3 with at most 1% of the liquid particles
// outside: compare::LongRunStabilityOptions). The trajectory is never loaded: memory is
// O(particles) whatever the duration. owval ci validate --stability 10s.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

#include "owval/ci/gates.hpp"
#include "owval/engine/config.hpp"

namespace owval::ci {

struct StreamedStabilityOptions {
  double duration_s = 10;     // simulated time
  int log_step = 20;          // steps between checked (and written) frames
  std::filesystem::path out;  // where the run's trajectory goes (engine/long_run.hpp outputs)
  std::string backend = "pcisph";
  std::function<void(std::size_t, std::size_t)> on_step;  // (steps done, total); may be empty
};

// One gate: passes when every frame passes; a NaN (SimulationError) fails it naming the step and
// particle. InputError for a configuration or output directory that cannot be used.
GateReport StreamedStability(const engine::SiberneticConfig& config,
                             const StreamedStabilityOptions& options);

// "10s", "10 s" or "10" → 10 (seconds); "500ms" → 0.5. InputError naming `flag` otherwise.
double ParseDuration(const std::string& text, const std::string& flag);

}  // namespace owval::ci
