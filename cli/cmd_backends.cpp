// owval backends list | show NAME: what each backend name resolves to (backends/registry.hpp).
#include <iostream>

#include "backend_flags.hpp"
#include "command.hpp"

namespace owval::cli {
namespace {

void List(const BackendFlags& flags, bool json) {
  const backends::Registry registry = flags.Registry();
  std::cout << (json ? registry.ToJson().dump(2) + "\n" : registry.ToText());
}

void SetUp(CLI::App& app) {
  auto flags = std::make_shared<BackendFlags>();
  auto json = std::make_shared<bool>(false);
  auto name = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("backends", "Backends by name: built in and user-defined");
  cmd->require_subcommand(1);
  CLI::App* list = cmd->add_subcommand("list", "Every backend name and what it resolves to");
  AddBackendFlags(list, flags.get(), false);
  list->add_flag("--json", *json, "Machine-readable output");
  list->callback([flags, json] { List(*flags, *json); });
  CLI::App* show = cmd->add_subcommand("show", "One backend's full definition (JSON)");
  AddBackendFlags(show, flags.get(), false);
  show->add_option("name", *name, "Backend name")->required();
  show->callback(
      [flags, name] { std::cout << flags->Registry().Find(*name).ToJson().dump(2) << "\n"; });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
