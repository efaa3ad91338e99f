#pragma once
// Running a simulation in process: configuration in, trajectory out. This is the engine's whole
// public surface for the harness (owval run, fits, benchmarks); solver internals stay inside.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

#include "owval/engine/config.hpp"
#include "owval/engine/muscles.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::engine {

enum class Integrator { kSemiImplicitEuler, kLeapfrog };  // Sibernetic's modes 2 and 0/1

struct RunOptions {
  double duration_s = 0.05;  // steps = (int)(duration_s / dt) computed in float, as Sibernetic
  int log_step = 1;          // a frame after step k when k % log_step == 0
  // The time-step scheme, by name (KnownBackends() in solver.hpp; "owval" is an alias of
  // "pcisph"). An unknown name is an InputError listing the known ones.
  std::string backend = "pcisph";
  Integrator integrator = Integrator::kSemiImplicitEuler;
  PhysicsConstants constants;  // Sibernetic's defaults unless changed
  // Apply the configuration's [physical parameters] block (Sibernetic ignores it). When true,
  // the result is labelled as no longer reference-equivalent in its provenance.
  bool apply_physical_parameters = false;
  // Where muscle activations come from; kAuto follows Sibernetic (waves for "worm" files).
  MuscleSignal muscle_signal = MuscleSignal::kAuto;
  int threads = 0;            // 0: OpenMP default
  bool record_fields = true;  // store velocity, density and pressure per frame
  // Where the state dump goes when a NaN appears (owval_nan_dump_step<k>.txt); empty: no dump.
  std::filesystem::path dump_dir;
  // Called after every step with (steps done, total steps); may be empty.
  std::function<void(std::size_t, std::size_t)> on_step;
};

struct RunSummary {
  std::size_t steps = 0;
  std::size_t frames = 0;
  double wall_s = 0;
  double steps_per_s = 0;
  bool reference_equivalent = true;   // false when constants differ from Sibernetic's
  bool muscles_driven = false;        // activations came from MuscleSimulation's waves
  std::vector<std::string> warnings;  // e.g. "[physical parameters] parsed but not applied"
  // Per recorded frame, the solver's TakeStepLog() (adaptive schemes: wcsph); empty otherwise.
  std::vector<std::string> frame_log;
};

// Runs the configuration with the solver options.backend names (MakeSolver in solver.hpp) and
// records a frame every log_step steps. Throws InputError for a configuration the engine cannot
// run (particle outside the box, connection to a missing particle, ...), an unknown backend or a
// non-physical constant. When a NaN appears it throws InputError naming the step and particle,
// after writing a state dump into options.dump_dir when one is given (path in the message).
Trajectory Run(const SiberneticConfig& config, const RunOptions& options,
               RunSummary* summary = nullptr);

}  // namespace owval::engine
