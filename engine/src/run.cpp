// Run(): configuration in, trajectory out.
#include "owval/engine/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string_view>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/one_line.hpp"
#include "owval/engine/constants.hpp"
#include "owval/engine/solver.hpp"
#include "state/particle_state.hpp"

namespace owval::engine {
namespace {

constexpr char kStateDumpPrefix[] = "owval_nan_dump_step";

// Moving particles must start inside the box (within float rounding of its faces). Boundary
// particles never move and only need a cell: Sibernetic's hash truncates toward zero, so a wall
// layer up to 2h beyond a face still bins correctly (test_gravity's walls sit 0.167 cu outside);
// owval allows h.
void CheckRunnable(const SiberneticConfig& c, float h_cu) {
  const Box& b = c.box;
  if (!(b.xmax > b.xmin && b.ymax > b.ymin && b.zmax > b.zmin))
    throw InputError(c.source, 0,
                     "the simulation box is empty or missing (xmax > xmin etc. expected)");
  constexpr float kMovingTolerance = 0.01f;
  for (std::size_t i = 0; i < c.particle_count(); ++i) {
    const Row4& p = c.position[i];
    const bool boundary = internal::IsBoundary(p[3]);
    const float t = boundary ? h_cu : kMovingTolerance;
    if (p[0] < b.xmin - t || p[0] > b.xmax + t || p[1] < b.ymin - t || p[1] > b.ymax + t ||
        p[2] < b.zmin - t || p[2] > b.zmax + t) {
      std::ostringstream msg;
      msg << (boundary ? "boundary" : "moving") << " particle " << i << " at (" << p[0] << ", "
          << p[1] << ", " << p[2] << ") is outside the simulation box by more than " << t << " cu ("
          << (boundary ? "h" : "rounding") << ")";
      throw InputError(c.source, 0, msg.str());
    }
  }
}

// (int)(timelimit / dt) in float, as Sibernetic computes it (owConfigProperty.cpp:136). A run
// of no step, or of more steps than any machine finishes, is refused before it starts.
std::size_t StepCount(const std::string& source, double duration_s, double time_step_s) {
  const float steps = float(duration_s) / float(time_step_s);
  constexpr float kMaxSteps = 1e12f;
  if (!(steps >= 1 && steps <= kMaxSteps)) {
    std::ostringstream msg;
    msg << "duration " << duration_s << " s with time step " << time_step_s << " s gives " << steps
        << " steps: expected 1 to " << kMaxSteps;
    throw InputError(source, 0, msg.str());
  }
  return static_cast<std::size_t>(steps);
}

// The frame buffers of a run, reused from frame to frame.
struct FrameBuffers {
  std::vector<float> positions, velocities, density, pressure;
};

FrameView Capture(const Solver& solver, bool fields, FrameBuffers* b) {
  const std::span<const Float4> x = solver.positions();
  b->positions.clear();
  for (const Float4& p : x) b->positions.insert(b->positions.end(), {p.x, p.y, p.z});
  FrameView f;
  f.positions = b->positions;
  if (!fields) return f;
  const std::span<const Float4> v = solver.velocities();
  b->velocities.clear();
  for (std::size_t i = 0; i < x.size(); ++i) {
    // A boundary's slot holds its normal: it does not move.
    if (internal::IsBoundary(x[i].w)) {
      b->velocities.insert(b->velocities.end(), {0.0f, 0.0f, 0.0f});
    } else {
      b->velocities.insert(b->velocities.end(), {v[i].x, v[i].y, v[i].z});
    }
  }
  b->density = solver.Density();
  const std::span<const float> pressure = solver.pressure();
  b->pressure.assign(pressure.begin(), pressure.end());
  f.velocities = b->velocities, f.density = b->density, f.pressure = b->pressure;
  return f;
}

// Keeps every frame: the in-memory Run.
class MemorySink : public FrameSink {
 public:
  MemorySink(Trajectory* t, std::vector<std::string>* step_logs) : t_(t), step_logs_(step_logs) {}
  void Begin(const Trajectory& header, int /*threads*/) override { *t_ = header; }
  void Frame(const FrameView& f) override {
    t_->AppendFrame(f.time_s, f.positions.data());
    t_->velocities.insert(t_->velocities.end(), f.velocities.begin(), f.velocities.end());
    t_->density.insert(t_->density.end(), f.density.begin(), f.density.end());
    t_->pressure.insert(t_->pressure.end(), f.pressure.begin(), f.pressure.end());
    if (!f.step_log.empty()) step_logs_->emplace_back(f.step_log);
  }

 private:
  Trajectory* t_;
  std::vector<std::string>* step_logs_;
};

// Writes the solver's state into dir (atomically) and returns the file's path; "" without dir.
std::string DumpState(const Solver& solver, std::size_t step, const std::filesystem::path& dir) {
  if (dir.empty()) return "";
  const std::filesystem::path path = StateDumpPath(dir, step);
  std::ostringstream out;
  out << "# owval engine (" << solver.name() << ") state at step " << step
      << ": index x y z type vx vy vz density pressure\n";
  const std::span<const Float4> x = solver.positions(), v = solver.velocities();
  const std::vector<float> density = solver.Density();
  const std::span<const float> pressure = solver.pressure();
  for (std::size_t i = 0; i < x.size(); ++i)
    out << i << ' ' << x[i].x << ' ' << x[i].y << ' ' << x[i].z << ' ' << x[i].w << ' ' << v[i].x
        << ' ' << v[i].y << ' ' << v[i].z << ' ' << (i < density.size() ? density[i] : NAN) << ' '
        << (i < pressure.size() ? pressure[i] : NAN) << '\n';
  std::filesystem::create_directories(dir);
  WriteFileAtomically(path, out.str());
  return path.string();
}

void Provenance(const SiberneticConfig& config, const RunOptions& o, const PhysicsConstants& c,
                const Solver& solver, Trajectory* t) {
  const bool equivalent = solver.reference_equivalent();
  t->provenance["producer"] = "owval engine " + solver.name();
  if (solver.name() == "pcisph") {
    t->provenance["engine_reference"] =
        "Sibernetic PCISPH (openworm/sibernetic 8d2df73) re-implemented on the CPU";
    t->provenance["integrator"] =
        o.integrator == Integrator::kLeapfrog ? "leapfrog" : "semi-implicit euler";
  } else {
    t->provenance["engine_reference"] =
        "not Sibernetic's scheme: " + solver.name() + " over Sibernetic's configuration";
  }
  t->provenance["configuration"] = config.source;
  t->provenance["reference_equivalent"] = equivalent ? "true" : "false";
  const std::string differences = c.DifferencesFromDefaults();
  t->provenance["constants"] = differences.empty() ? "Sibernetic defaults" : differences;
  const std::string parameters = solver.parameters();
  if (!parameters.empty()) t->provenance["scheme_parameters"] = parameters;
}

void StopOnNonFinite(const Solver& solver, std::size_t k, const RunOptions& options) {
  const auto [bad, quantity] = solver.FirstNonFinite();
  if (bad < 0) return;
  const std::string dump = DumpState(solver, k, options.dump_dir);
  throw SimulationError("NaN at step " + std::to_string(k) + " in particle " + std::to_string(bad) +
                        " (" + quantity + ")" +
                        (dump.empty() ? " (no state dump: no dump directory given)"
                                      : " (state dumped to " + dump + ")"));
}

// Frames recorded after steps [0, steps): one per k with k % log_step == 0.
std::size_t FramesBefore(std::size_t steps, std::size_t log_step) {
  return (steps + log_step - 1) / log_step;
}

// The trajectory's metadata (no frames) for FrameSink::Begin.
Trajectory Header(const SiberneticConfig& config, const RunOptions& options,
                  const PhysicsConstants& constants, const Solver& solver, bool muscles) {
  Trajectory t;
  t.box = config.box;
  t.time_step_s = constants.time_step_s;
  t.log_step = std::max(1, options.log_step);
  for (const Row4& p : config.position) t.type.push_back(p[3]);
  Provenance(config, options, constants, solver, &t);
  t.provenance["muscle_signal"] =
      muscles ? "main_sim.MuscleSimulation swimming/crawling waves (owval closed form)"
              : "none (all activations zero)";
  return t;
}

void Checkpoint(const Solver& solver, std::size_t frames, FrameSink* sink, bool stopping) {
  std::string state;
  solver.SaveState(&state);
  sink->Checkpoint(solver.steps_done(), frames, state, stopping);
}

// The caller's constants, with the configuration's [physical parameters] applied only when
// asked: Sibernetic parses them and never applies them, which a warning says.
PhysicsConstants RunConstants(const SiberneticConfig& config, const RunOptions& options,
                              std::vector<std::string>* warnings) {
  PhysicsConstants constants = options.constants;
  if (config.physical_parameters.empty()) return constants;
  if (options.apply_physical_parameters) {
    ApplyPhysicalParameters(config, &constants);
  } else {
    warnings->push_back(config.source +
                        ": [physical parameters] parsed but not applied, as Sibernetic does "
                        "(pass --apply-physical-parameters to apply them)");
  }
  return constants;
}

// The run's solver, ready for its first step: a backend that cannot checkpoint says so before
// it, and a resumed run's state is restored (refused when it is past the run's last step).
std::unique_ptr<Solver> ReadySolver(const SiberneticConfig& config, const RunOptions& options,
                                    const PhysicsConstants& constants, std::size_t steps) {
  RunOptions solver_options = options;
  solver_options.constants = constants;
  std::unique_ptr<Solver> made = MakeSolver(config, solver_options);
  Solver& solver = *made;
  if (options.checkpoint_every > 0) {
    std::string probe;  // a backend that cannot checkpoint says so before the first step
    solver.SaveState(&probe);
  }
  if (!options.resume_state.empty()) {
    solver.RestoreState(options.resume_state, options.resume_source);
    if (solver.steps_done() > steps)
      throw InputError(options.resume_source, 0,
                       "the checkpoint is at step " + std::to_string(solver.steps_done()) +
                           ", past the run's " + std::to_string(steps) + " steps");
  }
  return made;
}

// Whether the caller asked the run to stop before its next step; the stop writes a checkpoint
// when the solver can.
bool StopRequested(const Solver& solver, const RunOptions& options, std::size_t frames,
                   FrameSink* sink, RunSummary* sum) {
  if (!options.stop_requested || !options.stop_requested()) return false;
  sum->interrupted = true;
  sum->checkpointed = solver.can_checkpoint();
  if (sum->checkpointed) Checkpoint(solver, frames, sink, /*stopping=*/true);
  return true;
}

// One step; false when it was stopped within (wcsph's sub-steps), which leaves no checkpoint.
bool StepUnlessCancelled(Solver& solver, RunSummary* sum) {
  try {
    solver.Step();
  } catch (const Cancelled&) {
    sum->interrupted = true;
    return false;
  }
  return true;
}

// Sibernetic asks for the next activations after each step; step k + 1 uses call k's.
void SetNextActivations(std::size_t k, Solver& solver) {
  const auto signal = MuscleSimulationSignal(double(k));
  std::copy(signal.begin(), signal.end(), solver.muscle_activation().begin());
}

// The frame recorded after step k (the `*frames`-th): positions (and fields when asked), time
// and the scheme's step log.
void RecordFrame(Solver& solver, const RunOptions& options, const PhysicsConstants& constants,
                 std::size_t k, std::size_t* frames, FrameBuffers* buffers, FrameSink* sink) {
  FrameView f = Capture(solver, options.record_fields, buffers);
  f.index = (*frames)++, f.step = k, f.time_s = double(k) * constants.time_step_s;
  const std::string step_log = solver.TakeStepLog();
  f.step_log = step_log;
  sink->Frame(f);
}

// Steps [sum->first_step, steps) with a frame every log_step steps and a checkpoint every
// checkpoint_every (none after the last step); returns the frames recorded, the resumed run's
// earlier ones included.
std::size_t RunSteps(Solver& solver, const RunOptions& options, const PhysicsConstants& constants,
                     std::size_t steps, FrameSink* sink, RunSummary* sum) {
  const std::size_t log_step = std::size_t(std::max(1, options.log_step));
  std::size_t frames = FramesBefore(sum->first_step, log_step);
  FrameBuffers buffers;
  for (std::size_t k = sum->first_step; k < steps; ++k) {
    if (StopRequested(solver, options, frames, sink, sum)) break;
    if (!StepUnlessCancelled(solver, sum)) break;
    if (sum->muscles_driven) SetNextActivations(k, solver);
    StopOnNonFinite(solver, k, options);
    if (k % log_step == 0) RecordFrame(solver, options, constants, k, &frames, &buffers, sink);
    if (options.on_step) options.on_step(k + 1, steps);
    if (options.checkpoint_every > 0 && (k + 1) % options.checkpoint_every == 0 && k + 1 < steps)
      Checkpoint(solver, frames, sink, /*stopping=*/false);
  }
  return frames;
}

}  // namespace

std::filesystem::path StateDumpPath(const std::filesystem::path& dir, std::size_t step) {
  return dir / (kStateDumpPrefix + std::to_string(step) + ".txt");
}

bool IsStateDumpName(const std::filesystem::path& file) {
  const std::string name = file.filename().string();
  const std::string_view prefix(kStateDumpPrefix), suffix(".txt");
  if (name.size() <= prefix.size() + suffix.size() || !name.starts_with(prefix) ||
      !name.ends_with(suffix))
    return false;
  const std::string step = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return step.find_first_not_of("0123456789") == std::string::npos;
}

RunSummary Run(const SiberneticConfig& config, const RunOptions& options, FrameSink* sink) {
  RunSummary sum;
  const PhysicsConstants constants = RunConstants(config, options, &sum.warnings);
  CanonicalBackend(options.backend);  // an unknown name fails before any other check
  ValidateConstants(constants);
  const std::size_t steps = StepCount(config.source, options.duration_s, constants.time_step_s);
  CheckRunnable(config, float(constants.h_cu));
  const std::unique_ptr<Solver> made = ReadySolver(config, options, constants, steps);
  Solver& solver = *made;
  sum.reference_equivalent = solver.reference_equivalent();
  sum.muscles_driven = DrivesMuscles(options.muscle_signal, config.source);
  sink->Begin(Header(config, options, constants, solver, sum.muscles_driven), solver.threads());
  sum.first_step = solver.steps_done();
  const auto start = std::chrono::steady_clock::now();
  sum.frames = RunSteps(solver, options, constants, steps, sink, &sum);
  sum.steps = solver.steps_done();
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sum.steps_per_s = sum.wall_s > 0 ? double(sum.steps - sum.first_step) / sum.wall_s : 0;
  return sum;
}

Trajectory Run(const SiberneticConfig& config, const RunOptions& options, RunSummary* summary) {
  Trajectory t;
  std::vector<std::string> step_logs;
  MemorySink sink(&t, &step_logs);
  RunSummary s = Run(config, options, &sink);
  s.frame_log = std::move(step_logs);
  if (summary) *summary = std::move(s);
  return t;
}

Integrator ParseIntegrator(const std::string& name) {
  if (name == "euler") return Integrator::kSemiImplicitEuler;
  if (name == "leapfrog") return Integrator::kLeapfrog;
  throw InputError("integrator: expected euler or leapfrog, found '" + OneLine(name, 40) + "'");
}

const char* IntegratorName(Integrator integrator) {
  return integrator == Integrator::kLeapfrog ? "leapfrog" : "euler";
}

}  // namespace owval::engine
