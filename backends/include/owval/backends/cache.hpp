#pragma once
// The run cache: one directory per run, named by a SHA-256 key of everything that decides the
// result (the backend's resolved command, the configuration file's bytes, time, time step, log
// step). A run is written into a temporary sibling and renamed into place only when complete, so
// a failed or interrupted run never enters the cache.
#include <filesystem>
#include <optional>
#include <string>

namespace owval::backends {

struct CacheOptions {
  std::filesystem::path directory;  // --cache; DefaultCacheDirectory() when empty
  bool enabled = true;              // false: --no-cache (runs go to a temporary directory)
};

// $XDG_CACHE_HOME/owval, else $HOME/.cache/owval.
std::filesystem::path DefaultCacheDirectory();

// The key (64 hex digits). `resolved_command` names the run's producer with every value but the
// configuration path and output directory substituted; numbers enter with 17 digits.
std::string RunKey(const std::string& resolved_command, const std::string& configuration_bytes,
                   double time_s, double time_step_s, int log_step);

class RunCache {
 public:
  explicit RunCache(const CacheOptions& options);
  bool enabled() const { return enabled_; }
  // The completed run's directory, when the cache holds it.
  std::optional<std::filesystem::path> Find(const std::string& key) const;
  // A fresh, empty temporary directory for a run of `key` (removed again unless committed).
  std::filesystem::path Begin(const std::string& key) const;
  // Renames the temporary directory into the cache; returns the final directory. Without a
  // cache, returns `temporary` unchanged.
  std::filesystem::path Commit(const std::filesystem::path& temporary,
                               const std::string& key) const;

 private:
  std::filesystem::path directory_;
  bool enabled_;
};

}  // namespace owval::backends
