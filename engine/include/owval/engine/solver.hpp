#pragma once
// One time-step scheme behind one interface: what Run records, dumps and checks, whatever the
// scheme. A solver owns its particle state; it is built by MakeSolver from a configuration and
// the run's options, the scheme chosen by RunOptions::backend (a name, see KnownBackends()).
// The layout follows SPlisHSPlasH's (a class per scheme with step(), sharing kernels, neighbour
// search and forces): PCISPH lives in engine/src/pcisph/, a later scheme adds its own folder.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/engine/float4.hpp"
#include "owval/engine/run.hpp"

namespace owval::engine {

class Solver {
 public:
  virtual ~Solver() = default;

  // Advances one time step of the constants' time_step_s.
  virtual void Step() = 0;
  // Steps done since construction.
  virtual std::size_t steps_done() const = 0;
  // The backend name that built this solver ("pcisph", ...).
  virtual std::string name() const = 0;
  // The OpenMP threads a step runs on (MakeSolver's choice, or RunOptions::threads).
  virtual int threads() const = 0;
  // True when the run reproduces Sibernetic's OpenCL output (same scheme, same constants).
  virtual bool reference_equivalent() const = 0;

  // Per particle, in the configuration's row order.
  virtual std::span<const Float4> positions() const = 0;   // cu; w = type code
  virtual std::span<const Float4> velocities() const = 0;  // m/s; boundary rows: wall normal
  // Density (kg/m^3) of every particle at the current positions; empty when the scheme has none.
  virtual std::vector<float> Density() const = 0;
  // Pressure (Pa) of every particle; empty when the scheme has none.
  virtual std::span<const float> pressure() const = 0;
  // Muscle activations (kMuscleCount values) the next step uses.
  virtual std::span<float> muscle_activation() = 0;

  // The scheme's own parameters as "name = value, ..." for a run's provenance ("" if none).
  virtual std::string parameters() const { return ""; }

  // The scheme's adaptive stepping since the last call, one JSON object (time step history,
  // rollbacks, density variation), or "" when the scheme steps at a fixed dt. Run asks at every
  // frame and returns the answers in RunSummary::frame_log.
  virtual std::string TakeStepLog() { return ""; }

  // The first moving (non-boundary) particle whose position is not finite, else the first whose
  // velocity is not; particle −1 when every one is finite. Checked after every step of a run:
  // schemes that keep a list of their moving particles check only those.
  struct NonFinite {
    std::int64_t particle = -1;
    const char* quantity = "";  // "position" or "velocity"
  };
  virtual NonFinite FirstNonFinite() const;

  // Per-phase wall time, for `owval bench engine`: once enabled, Step() adds each phase's
  // seconds (steady clock, two reads per phase) to phase_seconds(). Schemes without phases
  // report nothing.
  struct PhaseTime {
    std::string phase;
    double seconds = 0;
  };
  virtual void EnablePhaseTiming() {}
  virtual std::vector<PhaseTime> phase_seconds() const { return {}; }

  // Checkpoints (owval run --checkpoint-every, --resume). SaveState appends to `out` everything
  // the next Step() reads, as versioned binary opening with a header (magic, format version,
  // backend name, particle count, steps done); RestoreState reads it back into a solver built
  // from the same configuration and options, after which Step() continues exactly as the saved
  // solver would have, bit for bit. RestoreState throws InputError naming `source` for a blob of
  // another backend, format version or particle count, or a truncated one. A scheme that cannot
  // checkpoint keeps these defaults, which throw InputError "backend X cannot checkpoint".
  virtual void SaveState(std::string* out) const;
  virtual void RestoreState(const std::string& state, const std::string& source);
  // Whether SaveState works: an interrupted run of a scheme that cannot checkpoint keeps its
  // partial trajectory and simply leaves no checkpoint.
  virtual bool can_checkpoint() const { return false; }
};

// The canonical names of the built-in backends, in the order `owval run --help` lists them.
std::vector<std::string> KnownBackends();

// The canonical name of a backend name or alias ("owval" -> "pcisph"). Throws InputError naming
// the known backends for any other name.
std::string CanonicalBackend(const std::string& name);

// Builds the solver options.backend names for the configuration, with options.constants (the
// caller applies [physical parameters] first), options.integrator and options.threads as given
// (0 = OpenMP default). Throws InputError for an unknown backend or non-physical constants.
std::unique_ptr<Solver> MakeSolver(const SiberneticConfig& config, const RunOptions& options);

}  // namespace owval::engine
