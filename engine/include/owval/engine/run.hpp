#pragma once
// Running a simulation in process: configuration in, trajectory out. This is the engine's whole
// public surface for the harness (owval run, fits, benchmarks); solver internals stay inside.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "owval/engine/config.hpp"
#include "owval/engine/muscles.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::engine {

enum class Integrator { kSemiImplicitEuler, kLeapfrog };  // Sibernetic's modes 2 and 0/1
// "euler" (semi-implicit Euler, Sibernetic's default) or "leapfrog", as flags, run requests and
// checkpoints name them; any other name is InputError. IntegratorName is its inverse.
Integrator ParseIntegrator(const std::string& name);
const char* IntegratorName(Integrator integrator);

// The most threads a run may ask for: beyond the machine's cores threads only stall each other
// at barriers, and far beyond them the OpenMP runtime fails to start them (libgomp aborted at
// 50,000 threads here and crashed at 100,000).
inline constexpr int kMaxThreads = 1024;
// The engine's thread rule runs a configuration of fewer particles on one thread: fork/join and
// barriers cost more than they save there (solver.cpp, ThreadsFor).
inline constexpr std::size_t kFewestParticlesForThreads = 4096;

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
  // OpenMP threads: 0 for the engine's rule (every idle core; one below
  // kFewestParticlesForThreads), or 1 to kMaxThreads. More is an InputError (MakeSolver).
  int threads = 0;
  bool record_fields = true;  // store velocity, density and pressure per frame
  // Where the state dump goes when a NaN appears (owval_nan_dump_step<k>.txt); empty: no dump.
  std::filesystem::path dump_dir;
  // Called after every step with (steps done, total steps); may be empty.
  std::function<void(std::size_t, std::size_t)> on_step;

  // Long runs (streaming Run below). Every checkpoint_every steps (0: never) the solver's state
  // goes to FrameSink::Checkpoint.
  std::size_t checkpoint_every = 0;
  // Polled between steps (never from a signal handler); when it returns true the run checkpoints
  // and returns early with RunSummary::interrupted. May be empty.
  std::function<bool()> stop_requested;
  // A Solver::SaveState blob to continue from instead of the configuration's initial state
  // (owval run --resume); resume_source names it in errors. Empty: start at step 0.
  std::string resume_state;
  std::string resume_source;
};

// One recorded frame, valid during FrameSink::Frame only. Fields are empty when
// RunOptions::record_fields is false (velocities of boundary particles are 0: their slot holds a
// wall normal).
struct FrameView {
  std::size_t index = 0;  // frame number in the whole run (a resumed run continues the count)
  std::size_t step = 0;   // the frame follows this step (k % log_step == 0)
  double time_s = 0;      // step * time step
  std::span<const float> positions;   // 3 a particle, cu
  std::span<const float> velocities;  // 3 a particle, m/s
  std::span<const float> density;     // 1 a particle, kg/m^3
  std::span<const float> pressure;    // 1 a particle, Pa
  // The scheme's own record of the steps since the previous frame (Solver::TakeStepLog: WCSPH's
  // dt history, rollbacks, density variation), JSON; empty for schemes without one.
  std::string_view step_log;
};

// Where a streaming run sends its frames: memory stays O(particles) whatever the run's length.
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Once, before the first step: the run's trajectory metadata (box, time step, log step, types,
  // provenance) without frames, and the threads the solver steps on (a sink that works in
  // parallel uses as many, leaving the cores a one-thread run does not use to others).
  virtual void Begin(const Trajectory& header, int threads) = 0;
  virtual void Frame(const FrameView& frame) = 0;
  // Every RunOptions::checkpoint_every steps, and when a stop is requested (`stopping`: the run
  // ends after it): steps done, frames recorded so far and Solver::SaveState's blob. Default:
  // ignored.
  virtual void Checkpoint(std::size_t /*steps_done*/, std::size_t /*frames*/,
                          const std::string& /*solver_state*/, bool /*stopping*/) {}
};

struct RunSummary {
  std::size_t steps = 0;
  std::size_t frames = 0;
  double wall_s = 0;
  double steps_per_s = 0;
  bool reference_equivalent = true;   // false when constants differ from Sibernetic's
  bool muscles_driven = false;        // activations came from MuscleSimulation's waves
  bool interrupted = false;           // stop_requested returned true before the last step
  bool checkpointed = false;          // the interruption left a checkpoint (Solver::can_checkpoint)
  std::size_t first_step = 0;         // > 0 for a resumed run
  std::vector<std::string> warnings;  // e.g. "[physical parameters] parsed but not applied"
  // Per recorded frame, FrameView::step_log: kept by the in-memory Run only (a streaming run's
  // sink sees each one with its frame); empty for schemes without one.
  std::vector<std::string> frame_log;
};

// Runs the configuration with the solver options.backend names (MakeSolver in solver.hpp) and
// sends a frame to `sink` every log_step steps. Throws InputError for a configuration the engine
// cannot run (particle outside the box, connection to a missing particle, ...), an unknown
// backend, a non-physical constant or a resume state that does not fit. When a position or
// velocity becomes NaN or infinite it throws SimulationError naming the step, particle and
// quantity, after writing a state dump into options.dump_dir when one is given (path in the
// message).
RunSummary Run(const SiberneticConfig& config, const RunOptions& options, FrameSink* sink);

// The state dump a run that fails at `step` writes into `dir`: owval_nan_dump_step<step>.txt.
std::filesystem::path StateDumpPath(const std::filesystem::path& dir, std::size_t step);
// Whether `file`'s name is a state dump's (StateDumpPath's form, any step): an earlier failed
// run's dump in a directory a later run completes in is that run's to remove.
bool IsStateDumpName(const std::filesystem::path& file);

// The same with every frame kept in memory (tests, fits, short runs): memory grows with frames.
Trajectory Run(const SiberneticConfig& config, const RunOptions& options,
               RunSummary* summary = nullptr);

}  // namespace owval::engine
