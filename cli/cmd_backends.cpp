// owval backends list | show NAME: what each backend name resolves to (backends/registry.hpp).
#include <iostream>

#include "backend_flags.hpp"
#include "command.hpp"

namespace owval::cli {
namespace {

void SetUpBackends(CLI::App& app) {
  auto selection = std::make_shared<backends::BackendSelection>();
  auto json = std::make_shared<bool>(false);
  auto name = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("backends", "Backends by name: built in and user-defined");
  cmd->require_subcommand(1);
  CLI::App* list = cmd->add_subcommand("list", "Every backend name and what it resolves to");
  AddBackendFlags(list, selection.get(), false);
  AddJsonFlag(list, json.get(), "the list");
  list->callback([selection, json] {
    const backends::Registry registry = selection->Load();
    std::cout << (*json ? registry.ToJson().dump(2) + "\n" : registry.ToText());
  });
  CLI::App* show = cmd->add_subcommand("show", "One backend's full definition (JSON)");
  AddBackendFlags(show, selection.get(), false);
  AddInput(show, "name", name.get(), "Backend name");
  show->callback(
      [selection, name] { std::cout << selection->Load().Find(*name).ToJson().dump(2) << "\n"; });
}

const bool backends_registered = RegisterCommand(&SetUpBackends);

}  // namespace
}  // namespace owval::cli
