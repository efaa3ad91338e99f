#pragma once
// The flags of every command that names backends: --backends FILE, --cache DIR, --no-cache.
#include <CLI/CLI.hpp>

#include "command.hpp"
#include "owval/backends/commands.hpp"

namespace owval::cli {

inline void AddBackendFlags(CLI::App* cmd, backends::BackendSelection* selection, bool with_cache) {
  cmd->add_option("--backends", selection->file,
                  "Backends file (else ./owval-backends.json, else "
                  "$XDG_CONFIG_HOME/owval/backends.json); docs/backends.md")
      ->check(GivenName());
  if (!with_cache) return;
  cmd->add_option("--cache", selection->cache.directory,
                  "Run cache directory (default $XDG_CACHE_HOME/owval or ~/.cache/owval)")
      ->check(GivenName());
  cmd->add_flag_callback(
      "--no-cache", [selection] { selection->cache.enabled = false; },
      "Neither read nor write the run cache");
}

}  // namespace owval::cli
