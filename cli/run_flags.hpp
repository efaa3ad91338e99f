#pragma once
// The engine flags several commands share (run, fit, bench, pipeline, predict), each declared
// once: its name, its check and its help's meaning; `scope` finishes the help with what the
// command applies it to (", per evaluation", " for --phases").
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "command.hpp"
#include "owval/engine/constants.hpp"
#include "owval/engine/run.hpp"

namespace owval::cli {

// --time: simulated seconds (run takes any number: the engine says what it refuses).
inline CLI::Option* AddTimeFlag(CLI::App* cmd, double* time_s, const std::string& scope) {
  return cmd->add_option("--time", *time_s, "Simulated time in seconds" + scope);
}
inline CLI::Option* AddLogStepFlag(CLI::App* cmd, int* log_step, const std::string& scope = "") {
  return cmd->add_option("--log-step", *log_step, "Steps between frames" + scope)
      ->check(Positive());
}
// --backend: the time-step scheme; `scope` names the schemes the command takes.
inline CLI::Option* AddBackendFlag(CLI::App* cmd, std::string* backend, const std::string& scope) {
  return cmd->add_option("--backend", *backend, "Time-step scheme" + scope);
}
inline CLI::Option* AddThreadsFlag(CLI::App* cmd, int* threads, const std::string& scope,
                                   int fewest = 0) {
  return cmd->add_option("--threads", *threads, "OpenMP threads" + scope)
      ->check(CLI::Range(fewest, engine::kMaxThreads));
}
inline CLI::Option* AddIntegratorFlag(CLI::App* cmd, std::string* integrator,
                                      const std::string& scope = "") {
  return cmd
      ->add_option("--integrator", *integrator,
                   "Integrator" + scope + ": euler (Sibernetic's default) or leapfrog")
      ->check(CLI::IsMember({"euler", "leapfrog"}));
}
// --checkpoint-every of the XPBD reverse pass (fit --gradient analytic, bench gradient): the
// states it keeps, not run's checkpoint file.
inline CLI::Option* AddTapeCheckpointFlag(CLI::App* cmd, std::size_t* every,
                                          const std::string& scope = "") {
  return cmd->add_option("--checkpoint-every", *every,
                         "States kept every k steps (0: full tape)" + scope);
}
// --set NAME=VALUE: a constant overridden (run, predict).
inline CLI::Option* AddConstantOverrides(CLI::App* cmd, std::vector<std::string>* set,
                                         const std::string& scope = "") {
  std::string names;
  for (const engine::ConstantInfo& c : engine::PhysicsConstantTable())
    names += (names.empty() ? "" : ", ") + std::string(c.name);
  return cmd->add_option("--set", *set,
                         "Override a constant, NAME=VALUE (e.g. elasticity_coefficient=3e8)" +
                             scope + ". NAME: " + names);
}
// --param NAME=NUMBER: a scenario generator's parameter overridden (scenario generate, predict).
inline CLI::Option* AddGeneratorParams(CLI::App* cmd, std::vector<std::string>* params) {
  return cmd->add_option("--param", *params,
                         "Override a scenario generator parameter, NAME=NUMBER");
}

}  // namespace owval::cli
