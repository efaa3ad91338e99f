// owval ci quick-test|validate DIR: the CI gates as commands (exit 1 when a gate fails).
#include <iostream>

#include "command.hpp"
#include "owval/ci/gates.hpp"
#include "owval/ci/stability_run.hpp"
#include "owval/compare/stability.hpp"
#include "resolve.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {

struct StabilityArgs {
  ci::StreamedStabilityOptions options;
  std::string duration;
  std::string scenario = (SharedReference() / "demo1/configuration").string();
};

void RunValidateStability(StabilityArgs& a, bool json) {
  ci::StreamedStabilityOptions& o = a.options;
  if (o.out.empty()) throw InputError("owval ci validate --stability: give --out DIR");
  o.duration_s = ci::ParseDuration(a.duration, "--stability");
  const engine::SiberneticConfig config = ResolveConfig(a.scenario);
  Progress progress("stability", 0, QuietMode());
  o.on_step = [&](std::size_t done, std::size_t total) {
    if (done % 200 == 0 || done == total)
      progress.Update(done, "of " + std::to_string(total) + " steps");
  };
  const ci::GateReport report = ci::StreamedStability(config, o);
  progress.Finish();
  PrintReport(report, json, &ci::GateReport::ToText);
}

void SetUpCi(CLI::App& app) {
  CLI::App* group = app.add_subcommand("ci", "CI gates over an artifact directory");
  group->require_subcommand(1);
  auto dir = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* quick =
      group->add_subcommand("quick-test", "Runs completed: trajectories exist, parse, no NaN");
  AddInput(quick, "directory", dir.get());
  AddJsonFlag(quick, json.get(), "the gates");
  quick->callback(
      [dir, json] { PrintReport(ci::QuickTest(*dir), *json, &ci::GateReport::ToText); });
  CLI::App* validate =
      group->add_subcommand("validate", "Stability, incompressibility and parity gates");
  // Checked in the callback, not here: a check here runs before CLI11 names an unknown flag, so
  // `--stability 10s --backend bogus` (bogus taken as the directory) said "Directory does not
  // exist".
  validate->add_option("directory", *dir, "Artifact directory (reference.*, candidate.*)")
      ->check(GivenName());
  auto stability = std::make_shared<StabilityArgs>();
  CLI::Option* streamed = validate->add_option(
      "--stability", stability->duration,
      "Instead: run --scenario for this simulated time (10s, 500ms) and apply the stability "
      "gate to every frame as it is produced (" +
          compare::DescribeStability(compare::LongRunStabilityOptions()) + ")");
  validate
      ->add_option(
          "--scenario", stability->scenario,
          "With --stability: scenario name or configuration (default: the reference demo1)")
      ->check(GivenName())
      ->needs(streamed);  // `validate DIR --scenario worm` judged DIR and said nothing of it
  AddLogStepFlag(validate, &stability->options.log_step, " (with --stability)")->needs(streamed);
  AddOut(validate, &stability->options.out, "With --stability: where the run's trajectory goes")
      ->needs(streamed);
  auto reference = std::make_shared<std::string>();
  validate->add_option("--reference", *reference, "Trajectory the directory's reference must be")
      ->check(GivenName());
  AddJsonFlag(validate, json.get(), "the gates");
  validate->callback([dir, stability, reference, json] {
    if (!stability->duration.empty() && !dir->empty())
      throw InputError("owval ci validate: give DIRECTORY or --stability TIME, not both ('" + *dir +
                       "' given with --stability)");
    if (!stability->duration.empty()) return RunValidateStability(*stability, *json);
    if (dir->empty()) throw InputError("owval ci validate: give DIRECTORY or --stability TIME");
    PrintReport(ci::Validate(*dir, {}, *reference), *json, &ci::GateReport::ToText);
  });
}

const bool ci_registered = RegisterCommand(&SetUpCi);

}  // namespace
}  // namespace owval::cli
