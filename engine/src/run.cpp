// Run(): configuration in, trajectory out.
#include "owval/engine/run.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include "owval/base/errors.hpp"
#include "pcisph/pcisph.hpp"

namespace owval::engine {
namespace {

using internal::Pcisph;

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

std::size_t StepCount(double duration_s, double time_step_s) {
  // (int)(timelimit / dt) in float, as Sibernetic computes it (owConfigProperty.cpp:136).
  const float steps = float(duration_s) / float(time_step_s);
  return steps > 0 ? static_cast<std::size_t>(steps) : 0;
}

void RecordFrame(const Pcisph& solver, double time_s, bool fields, Trajectory* t) {
  const auto& s = solver.state();
  const std::size_t n = s.size();
  t->time_s.push_back(time_s);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& x = s.position[i];
    t->positions.insert(t->positions.end(), {x.x, x.y, x.z});
  }
  if (!fields) return;
  for (std::size_t i = 0; i < n; ++i) {
    const bool boundary = internal::IsBoundary(s.position[i].w);
    const auto& v = s.velocity[i];  // a boundary's slot holds its normal: it does not move
    if (boundary) {
      t->velocities.insert(t->velocities.end(), {0.0f, 0.0f, 0.0f});
    } else {
      t->velocities.insert(t->velocities.end(), {v.x, v.y, v.z});
    }
  }
  const std::vector<float> density = solver.DensityOfAll();
  t->density.insert(t->density.end(), density.begin(), density.end());
  t->pressure.insert(t->pressure.end(), s.pressure.begin(), s.pressure.end());
}

std::string DumpState(const Pcisph& solver, std::size_t step) {
  const std::string path = "owval_nan_dump_step" + std::to_string(step) + ".txt";
  std::ofstream out(path);
  out << "# owval engine state at step " << step
      << ": index x y z type vx vy vz density pressure\n";
  const auto& s = solver.state();
  for (std::size_t i = 0; i < s.size(); ++i)
    out << i << ' ' << s.position[i].x << ' ' << s.position[i].y << ' ' << s.position[i].z << ' '
        << s.position[i].w << ' ' << s.velocity[i].x << ' ' << s.velocity[i].y << ' '
        << s.velocity[i].z << ' ' << s.density[i] << ' ' << s.pressure[i] << '\n';
  return path;
}

void Provenance(const SiberneticConfig& config, const RunOptions& o, const PhysicsConstants& c,
                bool equivalent, Trajectory* t) {
  t->provenance["producer"] = "owval engine pcisph";
  t->provenance["engine_reference"] =
      "Sibernetic PCISPH (openworm/sibernetic 8d2df73) re-implemented on the CPU";
  t->provenance["integrator"] =
      o.integrator == Integrator::kLeapfrog ? "leapfrog" : "semi-implicit euler";
  t->provenance["configuration"] = config.source;
  t->provenance["reference_equivalent"] = equivalent ? "true" : "false";
  const std::string differences = c.DifferencesFromDefaults();
  t->provenance["constants"] = differences.empty() ? "Sibernetic defaults" : differences;
}

}  // namespace

Trajectory Run(const SiberneticConfig& config, const RunOptions& options, RunSummary* summary) {
  RunSummary local;
  RunSummary& sum = summary ? *summary : local;
  PhysicsConstants constants = options.constants;
  if (!config.physical_parameters.empty()) {
    if (options.apply_physical_parameters) {
      ApplyPhysicalParameters(config, &constants);
    } else {
      sum.warnings.push_back(config.source +
                             ": [physical parameters] parsed but not applied, as Sibernetic does "
                             "(pass --apply-physical-parameters to apply them)");
    }
  }
  CheckRunnable(config, float(constants.h_cu));
  const bool equivalent = constants.DifferencesFromDefaults().empty() &&
                          options.integrator == Integrator::kSemiImplicitEuler;
  sum.reference_equivalent = equivalent;
  // A few hundred moving particles do not pay for a second thread's fork/join and barrier costs
  // (and a busy machine makes those barriers stall): one thread unless there is real work.
  const std::size_t moving = config.elastic_count() + config.liquid_count();
  const int threads = options.threads > 0 ? options.threads
                      : moving < 4096     ? 1
                                          : omp_get_max_threads();
  Pcisph solver(config, constants, options.integrator, threads);
  sum.muscles_driven = options.muscle_signal == MuscleSignal::kSwimmingWaves ||
                       (options.muscle_signal == MuscleSignal::kAuto && NamesAWorm(config.source));
  Trajectory t;
  t.box = config.box;
  t.time_step_s = constants.time_step_s;
  t.log_step = std::max(1, options.log_step);
  for (const Row4& p : config.position) t.type.push_back(p[3]);
  Provenance(config, options, constants, equivalent, &t);
  t.provenance["muscle_signal"] =
      sum.muscles_driven ? "main_sim.MuscleSimulation swimming/crawling waves (owval closed form)"
                         : "none (all activations zero)";
  const std::size_t steps = StepCount(options.duration_s, constants.time_step_s);
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < steps; ++k) {
    solver.Step();
    // Sibernetic asks for the next activations after each step; step k + 1 uses call k's.
    if (sum.muscles_driven) {
      const auto signal = MuscleSimulationSignal(double(k));
      std::copy(signal.begin(), signal.end(), solver.muscle_activation().begin());
    }
    const std::int64_t bad = solver.FirstNonFinite();
    if (bad >= 0) {
      const std::string dump = DumpState(solver, k);
      throw InputError(config.source, 0,
                       "NaN at step " + std::to_string(k) + " in particle " + std::to_string(bad) +
                           " (state dumped to " + dump + ")");
    }
    if (k % std::size_t(t.log_step) == 0)
      RecordFrame(solver, double(k) * constants.time_step_s, options.record_fields, &t);
    if (options.on_step) options.on_step(k + 1, steps);
  }
  sum.steps = steps;
  sum.frames = t.frame_count();
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sum.steps_per_s = sum.wall_s > 0 ? double(steps) / sum.wall_s : 0;
  return t;
}

}  // namespace owval::engine
