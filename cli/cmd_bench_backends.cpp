// owval bench backends A B ... --scenario S: each backend timed as a whole process
// (backends/bench.hpp); JSON on stdout (and --json-out FILE) and a Markdown table (--markdown
// FILE).
#include <unistd.h>

#include <cstdio>

#include "backend_flags.hpp"
#include "command.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {

void RunBench(backends::BenchRequest& r) {
  r.options.owval_executable = std::filesystem::read_symlink("/proc/self/exe");
  if (!QuietMode() && isatty(2))
    r.options.on_progress = [](const std::string& s) {
      std::fprintf(stderr, "\rbench: %-50s", s.c_str());
    };
  const backends::BenchReport report = backends::BenchNamed(r);
  if (r.options.on_progress) std::fprintf(stderr, "\n");
  std::cout << report.ToJson().dump(2) << "\n";
  if (!QuietMode()) std::fprintf(stderr, "%s", report.ToMarkdown().c_str());
}

void SetUpBenchBackends(CLI::App& app) {
  auto r = std::make_shared<backends::BenchRequest>();
  r->reference_dir = SharedReference();
  CLI::App* cmd = Bench(app).add_subcommand(
      "backends", "The same scenario on each backend, timed as whole processes (wait4 rusage)");
  AddInput(cmd, "backends", &r->names, "Backend names; ratios are to the first");
  cmd->add_option("--scenario", r->scenario, "Scenario folder (configuration + meta.json)")
      ->required()
      ->check(GivenName());
  AddReferenceDir(cmd, &r->reference_dir, "", "../shared/reference");
  AddTimeFlag(cmd, &r->time_s, " instead of the scenario's")->check(Positive());
  cmd->add_option("--repeat", r->options.repeat, "Runs per backend (median and spread)")
      ->check(Positive());
  AddThreadsFlag(cmd, &r->options.threads, " of built-in backends, every run (default: all cores)",
                 1);
  AddBackendSets(cmd, &r->sets);
  // --json-out as in the other benchmarks; --json, its first name, still taken.
  cmd->add_option("--json-out,--json", r->json, "Also write the JSON result here")
      ->check(OutputPath());
  AddMarkdownOut(cmd, &r->markdown, "the table");
  AddBackendFlags(cmd, &r->backends, false);
  cmd->callback([r] { RunBench(*r); });
}

const bool bench_backends_registered = RegisterCommand(&SetUpBenchBackends);

}  // namespace
}  // namespace owval::cli
