#include "owval/backends/cache.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <random>

#include "owval/backends/sha256.hpp"
#include "owval/base/errors.hpp"

namespace owval::backends {
namespace fs = std::filesystem;

fs::path DefaultCacheDirectory() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "owval";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "owval";
  return fs::temp_directory_path() / "owval-cache";
}

std::string RunKey(const std::string& resolved_command, const std::string& configuration_bytes,
                   double time_s, double time_step_s, int log_step) {
  char numbers[128];
  std::snprintf(numbers, sizeof numbers, "time_s=%.17g time_step_s=%.17g log_step=%d", time_s,
                time_step_s, log_step);
  return Sha256Hex("owval run cache v1\ncommand=" + resolved_command +
                   "\nconfiguration_sha256=" + Sha256Hex(configuration_bytes) + "\n" + numbers);
}

RunCache::RunCache(const CacheOptions& options)
    : directory_(options.directory.empty() ? DefaultCacheDirectory() : options.directory),
      enabled_(options.enabled) {}

std::optional<fs::path> RunCache::Find(const std::string& key) const {
  std::error_code ec;
  if (!enabled_ || !fs::is_directory(directory_ / key, ec)) return std::nullopt;
  return directory_ / key;
}

fs::path RunCache::Begin(const std::string& key) const {
  const fs::path parent = enabled_ ? directory_ : fs::temp_directory_path();
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec)
    throw InputError(parent.string(), 0, "cannot create the cache directory: " + ec.message());
  std::random_device random;
  const fs::path dir = parent / (".tmp-" + key.substr(0, 16) + "-" + std::to_string(::getpid()) +
                                 "-" + std::to_string(random()));
  fs::create_directories(dir);
  return dir;
}

fs::path RunCache::Commit(const fs::path& temporary, const std::string& key) const {
  if (!enabled_) return temporary;
  const fs::path final_dir = directory_ / key;
  std::error_code ec;
  fs::rename(temporary, final_dir, ec);
  if (ec) {  // another process committed the same run first: keep theirs
    fs::remove_all(temporary, ec);
    if (!fs::is_directory(final_dir)) throw InputError(final_dir.string(), 0, "cannot commit run");
  }
  return final_dir;
}

}  // namespace owval::backends
