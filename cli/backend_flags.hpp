#pragma once
// The flags of every command that names backends: --backends FILE, --cache DIR, --no-cache.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "owval/backends/cache.hpp"
#include "owval/backends/registry.hpp"

namespace owval::cli {

struct BackendFlags {
  std::string file, cache;
  bool no_cache = false;
  backends::Registry Registry() const;
  backends::CacheOptions Cache() const;
};

void AddBackendFlags(CLI::App* cmd, BackendFlags* flags, bool with_cache);

// "NAME=VALUE" strings as a map (InputError naming --set otherwise).
std::map<std::string, std::string> ParseSets(const std::vector<std::string>& sets);

}  // namespace owval::cli
