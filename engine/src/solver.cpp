// The backend table: names, aliases and the factory of each built-in scheme.
#include "owval/engine/solver.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/engine/constants.hpp"
#include "pcisph/pcisph.hpp"
#include "state/non_finite.hpp"
#include "state/particle_state.hpp"
#include "wcsph/wcsph.hpp"
#include "xpbd/xpbd.hpp"

namespace owval::engine {
namespace {

struct BackendEntry {
  const char* name;
  std::vector<const char*> aliases;
  std::unique_ptr<Solver> (*make)(const SiberneticConfig&, const RunOptions&, int threads);
};

const std::vector<BackendEntry>& Backends() {
  static const std::vector<BackendEntry> table = {
      {"pcisph",
       {"owval"},
       [](const SiberneticConfig& c, const RunOptions& o, int threads) -> std::unique_ptr<Solver> {
         return std::make_unique<internal::Pcisph>(c, o.constants, o.integrator, threads);
       }},
      {"xpbd",
       {},
       [](const SiberneticConfig& c, const RunOptions& o, int threads) -> std::unique_ptr<Solver> {
         if (o.integrator != Integrator::kSemiImplicitEuler)
           throw InputError(
               "backend xpbd derives velocities from positions: it takes no "
               "--integrator (leapfrog is PCISPH's)");
         return std::make_unique<internal::Xpbd<float>>(c, o.constants, threads);
       }},
      {"wcsph",
       {},
       [](const SiberneticConfig& c, const RunOptions& o, int threads) -> std::unique_ptr<Solver> {
         if (o.integrator != Integrator::kSemiImplicitEuler)
           throw InputError(
               "backend wcsph integrates with velocity Verlet: it takes no --integrator "
               "(leapfrog is PCISPH's)");
         auto solver = std::make_unique<internal::Wcsph>(c, o.constants, threads);
         solver->set_stop_requested(o.stop_requested);  // polled between its sub-steps
         return solver;
       }},
  };
  return table;
}

const BackendEntry& Find(const std::string& name) {
  for (const BackendEntry& b : Backends()) {
    if (name == b.name) return b;
    for (const char* alias : b.aliases)
      if (name == alias) return b;
  }
  std::string known;
  for (const BackendEntry& b : Backends()) {
    known += known.empty() ? "" : ", ";
    known += b.name;
    for (const char* alias : b.aliases) known += std::string(" (alias ") + alias + ")";
  }
  throw InputError("unknown backend '" + name + "': expected one of " + known);
}

// Cores no other process is using now: the whole part of the one-minute load average taken from
// cores OpenMP would use. The output does not depend on the thread count (every particle's
// arithmetic is the same on any thread), only the speed does.
int IdleCores() {
  const int cores = omp_get_max_threads();
  double load = 0;
  if (getloadavg(&load, 1) != 1) return cores;
  return std::clamp(cores - int(std::floor(load)), 1, cores);
}

// Small scenes do not pay for a second thread's fork/join and barriers. Above that, every idle
// core: on an idle 2-core machine demo1 1 s runs in 18.2 s on two threads vs 22.8 s on one, the
// worm in 84.4 s vs 126.1 s; but threads that share a core with another busy process stall at
// every barrier (the worm ran 8x slower on two threads than on one under a load of 10).
int ThreadsFor(const SiberneticConfig& config, int requested) {
  if (requested < 0 || requested > kMaxThreads)
    throw InputError("threads: expected 0 (every idle core) or 1 to " +
                     std::to_string(kMaxThreads) + ", found " + std::to_string(requested));
  if (requested > 0) return requested;
  return config.particle_count() < kFewestParticlesForThreads ? 1 : IdleCores();
}

}  // namespace

Solver::NonFinite Solver::FirstNonFinite() const {
  const std::span<const Float4> x = positions();
  // A plain index list, not a std::views::filter: clang 14 (the fuzz build's compiler) cannot
  // instantiate libstdc++ 12's <ranges>.
  std::vector<std::size_t> moving;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!internal::IsBoundary(x[i].w)) moving.push_back(i);
  return internal::FirstNonFiniteOf(x, velocities(), moving);
}

void Solver::SaveState(std::string*) const {
  throw InputError("backend " + name() + " cannot checkpoint (no --checkpoint-every or --resume)");
}

void Solver::RestoreState(const std::string&, const std::string& source) {
  throw InputError(source, 0, "backend " + name() + " cannot checkpoint: nothing to resume");
}

std::vector<std::string> KnownBackends() {
  std::vector<std::string> names;
  for (const BackendEntry& b : Backends()) names.push_back(b.name);
  return names;
}

std::string CanonicalBackend(const std::string& name) { return Find(name).name; }

std::unique_ptr<Solver> MakeSolver(const SiberneticConfig& config, const RunOptions& options) {
  const BackendEntry& backend = Find(options.backend);
  ValidateConstants(options.constants);
  return backend.make(config, options, ThreadsFor(config, options.threads));
}

}  // namespace owval::engine
