// owval bench engine CONFIG|demo1|one_sprig|<reference folder>: a solver's in-process speed, or
// with --phases / --whole-run where a run's time goes (backends/engine_bench.hpp). JSON on stdout.
#include <filesystem>
#include <iostream>

#include "command.hpp"
#include "owval/backends/engine_bench.hpp"
#include "owval/base/atomic_output.hpp"

namespace owval::cli {
namespace {
namespace fs = std::filesystem;

struct BenchEngineArgs {
  std::string config = "demo1";
  std::string json_out;
  bool whole_run = false;
  backends::EngineBenchOptions options;
};

void RunBench(const BenchEngineArgs& a) {
  if (!a.json_out.empty()) CheckOutputPath(a.json_out);
  const nlohmann::json out = backends::BenchEngineNamed(
      a.config, fs::path(OWVAL_SHARED_DIR) / "reference", DataDir(), a.whole_run, a.options);
  std::cout << out.dump(2) << "\n";
  if (!a.json_out.empty()) WriteFileAtomically(a.json_out, out.dump(2) + "\n");
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<BenchEngineArgs>();
  backends::EngineBenchOptions& o = a->options;
  CLI::App* cmd = Bench(app).add_subcommand(
      "engine", "PCISPH engine speed (steps/s), one thread and all threads");
  cmd->add_option("config", a->config,
                  "demo1, one_sprig (Sibernetic's files in ../shared), a scenario or a file");
  cmd->add_option("--steps", o.steps, "Steps to time");
  cmd->add_option("--json-out", a->json_out, "Also write the JSON result here");
  cmd->add_option("--backend", o.backend, "Solver to time (pcisph, xpbd; default pcisph)");
  cmd->add_flag("--phases", o.phases,
                "Time each phase of the step and the frames' fields (one run, --threads)");
  cmd->add_flag("--whole-run", a->whole_run,
                "With a reference folder: profile its whole run (meta.json's time and log step)");
  cmd->add_option("--threads", o.threads, "Threads for --phases (default: the engine's rule)");
  cmd->add_option("--time", o.time_s, "Simulated seconds for --phases instead of --steps")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--log-step", o.log_step, "Steps between frames for --phases")
      ->check(CLI::PositiveNumber);
  cmd->callback([a] { RunBench(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
