#pragma once
// The flags of every command that names backends: --backends FILE, --cache DIR, --no-cache,
// --set NAME=VALUE (a backend's {set:NAME}), --reference-dir DIR (the scenario folders).
#include <CLI/CLI.hpp>

#include "command.hpp"
#include "owval/backends/commands.hpp"

namespace owval::cli {

// --backends FILE; `of` says what the command takes from it (" of --fit-backend").
inline void AddBackendsFileFlag(CLI::App* cmd, std::string* file, const std::string& of = "") {
  cmd->add_option("--backends", *file,
                  "Backends file" + of +
                      " (else ./owval-backends.json, else $XDG_CONFIG_HOME/owval/backends.json); "
                      "docs/backends.md")
      ->check(GivenName());
}
inline void AddBackendFlags(CLI::App* cmd, backends::BackendSelection* selection, bool with_cache) {
  AddBackendsFileFlag(cmd, &selection->file);
  if (!with_cache) return;
  cmd->add_option("--cache", selection->cache.directory,
                  "Run cache directory (default $XDG_CACHE_HOME/owval or ~/.cache/owval)")
      ->check(GivenName());
  cmd->add_flag_callback(
      "--no-cache", [selection] { selection->cache.enabled = false; },
      "Neither read nor write the run cache");
}

// `scope` says when the command uses them ("With backend names: ").
inline void AddBackendSets(CLI::App* cmd, std::vector<std::string>* sets,
                           const std::string& scope = "") {
  cmd->add_option("--set", *sets, scope + "NAME=VALUE for {set:NAME}");
}
template <class T>
void AddReferenceDir(CLI::App* cmd, T* dir, const std::string& scope, const std::string& fallback) {
  const std::string folders =
      scope.empty() ? "The scenario folders" : scope + "the scenario folders";
  cmd->add_option("--reference-dir", *dir, folders + " (default: " + fallback + ")")
      ->check(GivenName());
}

}  // namespace owval::cli
