// owval ci quick-test|validate DIR: the CI gates as commands (exit 1 when a gate fails).
#include <iostream>

#include "command.hpp"
#include "owval/ci/gates.hpp"

namespace owval::cli {
namespace {

void Report(const ci::GateReport& report) {
  std::cout << report.ToText();
  if (!report.pass()) SetExitCode(1);
}

void SetUp(CLI::App& app) {
  CLI::App* group = app.add_subcommand("ci", "CI gates over an artifact directory");
  group->require_subcommand(1);
  auto dir = std::make_shared<std::string>();
  CLI::App* quick =
      group->add_subcommand("quick-test", "Runs completed: trajectories exist, parse, no NaN");
  quick->add_option("directory", *dir)->required()->check(CLI::ExistingDirectory);
  quick->callback([dir] { Report(ci::QuickTest(*dir)); });
  CLI::App* validate =
      group->add_subcommand("validate", "Stability, incompressibility and parity gates");
  validate->add_option("directory", *dir)->required()->check(CLI::ExistingDirectory);
  validate->callback([dir] { Report(ci::Validate(*dir)); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
