// ProfilePhases(): Run()'s loop with a clock around each part.
#include "owval/engine/profile.hpp"

#include <algorithm>
#include <chrono>

#include "owval/base/errors.hpp"
#include "owval/engine/constants.hpp"
#include "owval/engine/muscles.hpp"

namespace owval::engine {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point* mark) {
  const Clock::time_point now = Clock::now();
  const double s = std::chrono::duration<double>(now - *mark).count();
  *mark = now;
  return s;
}

// The copies Run() makes of a frame, kept so that the compiler cannot drop them.
std::size_t CopyFrame(const Solver& solver, bool fields) {
  std::vector<float> copy;
  for (const Float4& p : solver.positions()) copy.insert(copy.end(), {p.x, p.y, p.z});
  if (fields) {
    for (const Float4& v : solver.velocities()) copy.insert(copy.end(), {v.x, v.y, v.z});
    const std::vector<float> density = solver.Density();
    copy.insert(copy.end(), density.begin(), density.end());
    const std::span<const float> pressure = solver.pressure();
    copy.insert(copy.end(), pressure.begin(), pressure.end());
  }
  return copy.size();
}

}  // namespace

PhaseProfile ProfilePhases(const SiberneticConfig& config, const RunOptions& options) {
  RunOptions o = options;
  if (!config.physical_parameters.empty() && o.apply_physical_parameters)
    ApplyPhysicalParameters(config, &o.constants);
  const std::size_t steps =
      static_cast<std::size_t>(float(o.duration_s) / float(o.constants.time_step_s));
  const std::unique_ptr<Solver> solver = MakeSolver(config, o);
  solver->EnablePhaseTiming();
  const bool muscles = DrivesMuscles(o.muscle_signal, config.source);
  const std::size_t log_step = std::size_t(std::max(1, o.log_step));
  PhaseProfile p;
  p.backend = solver->name();
  p.threads = o.threads;
  p.steps = steps;
  std::size_t values = 0;
  const Clock::time_point start = Clock::now();
  Clock::time_point mark = start;
  for (std::size_t k = 0; k < steps; ++k) {
    solver->Step();
    Since(&mark);
    if (muscles) {
      const auto signal = MuscleSimulationSignal(double(k));
      std::copy(signal.begin(), signal.end(), solver->muscle_activation().begin());
      p.muscles_s += Since(&mark);
    }
    if (solver->FirstNonFinite().particle >= 0)
      throw InputError(config.source, 0, "NaN at step " + std::to_string(k));
    p.check_s += Since(&mark);
    if (k % log_step == 0) {
      values += CopyFrame(*solver, o.record_fields);
      ++p.frames;
      p.frame_s += Since(&mark);
    }
  }
  p.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  p.step = solver->phase_seconds();
  p.values_copied = values;
  return p;
}

}  // namespace owval::engine
