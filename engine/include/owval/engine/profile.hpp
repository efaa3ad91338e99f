#pragma once
// Where a run's time goes: the same steps as Run() (solver, muscle signal, a frame's fields every
// log_step steps) with the solver's per-phase clock on, and nothing written. For
// `owval bench engine --phases`; the end-to-end figure of a run is `owval bench backends`'s.
#include <cstddef>
#include <string>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/engine/solver.hpp"

namespace owval::engine {

struct PhaseProfile {
  std::string backend;
  int threads = 0;  // as MakeSolver chose them (0 in RunOptions: the engine's rule)
  std::size_t steps = 0, frames = 0;
  double wall_s = 0;                    // all steps and frames
  std::vector<Solver::PhaseTime> step;  // the solver's phases, summed over the steps
  // What Run() does besides Step(): the muscle signal, the NaN check and a frame's fields
  // (positions, velocities, Density(), pressure copied out) every log_step steps.
  double muscles_s = 0, check_s = 0, frame_s = 0;
  std::size_t values_copied = 0;  // floats a frame's copies held, summed over frames
};

// Runs config as Run(config, options) would (same steps, same frames) and times each part.
// Throws what Run() throws.
PhaseProfile ProfilePhases(const SiberneticConfig& config, const RunOptions& options);

}  // namespace owval::engine
