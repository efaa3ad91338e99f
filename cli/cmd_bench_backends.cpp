// owval bench backends A B ... --scenario S: each backend timed as a whole process
// (backends/bench.hpp); JSON on stdout (or --json FILE) and a Markdown table (--markdown FILE).
#include <unistd.h>

#include <filesystem>
#include <iostream>

#include "backend_flags.hpp"
#include "command.hpp"
#include "owval/backends/bench.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/run.hpp"

namespace owval::cli {
namespace {
namespace fs = std::filesystem;

struct BenchArgs {
  std::vector<std::string> names, sets;
  std::string scenario, reference_dir, json, markdown;
  double time_s = 0;
  int repeat = 3, threads = 0;
  BackendFlags backends;
};

void RunBench(const BenchArgs& a) {
  if (!a.json.empty()) CheckOutputPath(a.json);
  if (!a.markdown.empty()) CheckOutputPath(a.markdown);
  const backends::Registry registry = a.backends.Registry();
  std::vector<backends::Backend> chosen;
  for (const std::string& name : a.names) chosen.push_back(registry.Find(name));
  const fs::path root = a.reference_dir.empty() ? fs::path(OWVAL_SHARED_DIR) / "reference"
                                                : fs::path(a.reference_dir);
  backends::BenchOptions options;
  options.scenario = backends::FindScenarios(root, {a.scenario}).front();
  // `--json ../shared/reference/demo1/meta.json` would replace the scenario it times.
  std::vector<fs::path> inputs = {a.backends.file};
  for (const auto& entry : fs::directory_iterator(options.scenario.directory))
    inputs.push_back(entry.path());
  for (const std::string& out : {a.json, a.markdown})
    if (!out.empty()) CheckOutputIsNotAnInput(out, inputs);
  if (a.time_s > 0) options.scenario.time_s = a.time_s;
  options.repeat = a.repeat;
  options.threads = a.threads;
  options.owval_executable = fs::read_symlink("/proc/self/exe");
  options.sets = ParseSets(a.sets);
  if (!Flags().quiet && isatty(2))
    options.on_progress = [](const std::string& s) {
      std::fprintf(stderr, "\rbench: %-50s", s.c_str());
    };
  const backends::BenchReport report = backends::BenchBackends(chosen, options);
  if (options.on_progress) std::fprintf(stderr, "\n");
  if (!a.markdown.empty()) WriteFileAtomically(a.markdown, report.ToMarkdown());
  if (!a.json.empty()) WriteFileAtomically(a.json, report.ToJson().dump(2) + "\n");
  std::cout << report.ToJson().dump(2) << "\n";
  if (!Flags().quiet) std::fprintf(stderr, "%s", report.ToMarkdown().c_str());
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<BenchArgs>();
  CLI::App* cmd = Bench(app).add_subcommand(
      "backends", "The same scenario on each backend, timed as whole processes (wait4 rusage)");
  cmd->add_option("backends", a->names, "Backend names; ratios are to the first")->required();
  cmd->add_option("--scenario", a->scenario, "Scenario folder (configuration + meta.json)")
      ->required();
  cmd->add_option("--reference-dir", a->reference_dir,
                  "Where the scenario folders are (default ../shared/reference)");
  cmd->add_option("--time", a->time_s, "Simulated seconds instead of the scenario's")
      ->check(Positive());
  cmd->add_option("--repeat", a->repeat, "Runs per backend (median and spread)")->check(Positive());
  cmd->add_option("--threads", a->threads,
                  "Built-in backends' threads, every run (default: all cores)")
      ->check(CLI::Range(1, engine::kMaxThreads));
  cmd->add_option("--set", a->sets, "NAME=VALUE for {set:NAME}");
  cmd->add_option("--json", a->json, "Also write the JSON here");
  cmd->add_option("--markdown", a->markdown, "Write the Markdown table here");
  AddBackendFlags(cmd, &a->backends, false);
  cmd->callback([a] { RunBench(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
