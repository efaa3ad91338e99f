#pragma once
// owval bench engine: the in-process speed of a solver on one configuration (steps/s on one
// thread and on all, with the median step), or, with `phases`, where a run's time goes: each phase
// of the step and the frames' fields (engine::ProfilePhases), over a number of steps or a
// reference scenario's whole run (its meta.json's time and log step, beside Sibernetic's recorded
// wall time). The end-to-end figure (process start to last byte) is bench backends' (bench.hpp).
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "owval/backends/scenario_store.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/gradient.hpp"

namespace owval::backends {

struct EngineBenchOptions {
  std::string backend = "pcisph";
  std::size_t steps = 1000;
  bool phases = false;
  int threads = 0;  // for phases; 0: the engine's rule
  // Phases over the whole recorded run of this scenario instead of `steps` (null: not).
  const Scenario* whole_run = nullptr;
  double time_s = 0;  // phases: simulated seconds instead of steps (0: not given)
  int log_step = 0;   // phases: steps between frames (0: one frame)
};

// The JSON `owval bench engine` prints.
nlohmann::json BenchEngine(const engine::SiberneticConfig& config,
                           const EngineBenchOptions& options);

// The same on a configuration named as `owval bench engine` takes it: a folder of
// `reference_root` by name (demo1_1s, test_energy, ...), else a scenario of `data_dir` or a
// configuration file. `whole_run` profiles the reference folder's recorded run (InputError for
// anything but a folder with a configuration and meta.json).
nlohmann::json BenchEngineNamed(const std::string& name,
                                const std::filesystem::path& reference_root,
                                const std::filesystem::path& data_dir, bool whole_run,
                                EngineBenchOptions options);

// `owval bench gradient`: the XPBD reverse pass's cost per step against its forward pass and
// the memory its checkpointing holds, on a loss that touches every moving particle (each one's
// distance to its initial position at the window's last step). alpha_density < 0: the model's
// (0 is a value: a rigid density constraint).
nlohmann::json BenchGradient(const engine::SiberneticConfig& config,
                             const engine::GradientOptions& options, double alpha_density);

}  // namespace owval::backends
