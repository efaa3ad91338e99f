#include "backend_flags.hpp"

#include "owval/base/errors.hpp"

namespace owval::cli {

backends::Registry BackendFlags::Registry() const {
  return backends::LoadRegistry(backends::RegistryOptionsFromEnvironment(file));
}

backends::CacheOptions BackendFlags::Cache() const {
  return backends::CacheOptions{cache, !no_cache};
}

void AddBackendFlags(CLI::App* cmd, BackendFlags* flags, bool with_cache) {
  cmd->add_option("--backends", flags->file,
                  "Backends file (else ./owval-backends.json, else "
                  "$XDG_CONFIG_HOME/owval/backends.json); docs/backends.md");
  if (!with_cache) return;
  cmd->add_option("--cache", flags->cache,
                  "Run cache directory (default $XDG_CACHE_HOME/owval or ~/.cache/owval)");
  cmd->add_flag("--no-cache", flags->no_cache, "Neither read nor write the run cache");
}

std::map<std::string, std::string> ParseSets(const std::vector<std::string>& sets) {
  std::map<std::string, std::string> out;
  for (const std::string& s : sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--set " + s + ": expected NAME=VALUE");
    out[s.substr(0, eq)] = s.substr(eq + 1);
  }
  return out;
}

}  // namespace owval::cli
