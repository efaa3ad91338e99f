// owval scenario list|show|generate: the built-in scenario library.
#include <iostream>

#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/scenarios/scenario.hpp"
#include "run_flags.hpp"

namespace owval::cli {
namespace {

struct ScenarioArgs {
  std::string name, out;
  std::vector<std::string> params;
};

void SetUpScenario(CLI::App& app) {
  auto a = std::make_shared<ScenarioArgs>();
  CLI::App* cmd = app.add_subcommand("scenario", "Built-in scenarios: list, show, generate");
  cmd->require_subcommand(1);
  auto json = std::make_shared<bool>(false);
  CLI::App* list = cmd->add_subcommand("list", "List built-in scenarios");
  AddJsonFlag(list, json.get(), "the scenarios (name and description)");
  list->callback([json] {
    nlohmann::json listed = nlohmann::json::array();
    for (const std::string& name : scenarios::ListScenarios(DataDir())) {
      const scenarios::Scenario s = scenarios::LoadScenario(name, DataDir());
      if (*json)
        listed.push_back({{"name", name}, {"description", s.description}});
      else
        std::cout << name << "\t" << s.description << "\n";
    }
    if (*json) std::cout << listed.dump(2) << "\n";
  });
  CLI::App* show = cmd->add_subcommand("show", "Print a scenario's manifest");
  AddInput(show, "name", &a->name);
  show->callback(
      [a] { std::cout << scenarios::LoadScenario(a->name, DataDir()).manifest.dump(2) << "\n"; });
  CLI::App* generate =
      cmd->add_subcommand("generate", "Write a scenario's configuration in Sibernetic's format");
  AddInput(generate, "name", &a->name);
  AddOut(generate, &a->out, "Configuration file to write")->required();
  AddGeneratorParams(generate, &a->params);
  generate->callback([a] {
    const auto config = scenarios::GenerateConfigFile(scenarios::LoadScenario(a->name, DataDir()),
                                                      scenarios::ParseOverrides(a->params), a->out);
    std::cout << "wrote " << a->out << ": " << config.elastic_count() << " elastic, "
              << config.liquid_count() << " liquid, " << config.boundary_count()
              << " boundary particles\n";
  });
}

const bool scenario_registered = RegisterCommand(&SetUpScenario);

}  // namespace
}  // namespace owval::cli
