#pragma once
// One run of one backend on one scenario: fetched from a store, taken from the run cache, or
// run (the in-process engine for built-ins, the expanded command for command backends) and then
// cached. A command that fails, writes nothing or writes an unreadable trajectory is an
// InputError naming the backend, what went wrong and the tail of its stderr; nothing of it
// enters the cache. The trajectory is checked frame by frame and left in its file: callers read
// it frame by frame (RunOutcome::Frames).
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "owval/backends/cache.hpp"
#include "owval/backends/registry.hpp"
#include "owval/backends/scenario_store.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::backends {

struct RunRequest {
  Scenario scenario;  // its configuration, time, time step, log step; its name for stores
  std::map<std::string, std::string> sets;  // {set:NAME} values over the backend's defaults
};

struct RunOutcome {
  std::string source;  // "ran" | "cache hit" | "store"
  std::string detail;  // what was used, e.g. the store file or "fallback: ./Sibernetic missing"
  std::filesystem::path file;  // the trajectory file (absolute)
  double wall_s = 0;           // the run's wall time (0 for cache hits and stores)
  TextReadOptions reading;     // how `file` is read (its text layout)
  // A run with the cache off: its directory (holding `file`), removed when the last copy of the
  // outcome is destroyed.
  std::shared_ptr<const std::filesystem::path> uncached_directory;

  // The trajectory, frame by frame (memory O(particles), whatever the run's length).
  std::unique_ptr<FrameSource> Frames() const;
};

// The command line a command backend runs for `request` (values quoted), with {out} = out_dir.
std::string ResolvedCommand(const Backend& backend, const RunRequest& request,
                            const std::filesystem::path& out_dir);

// The cache key of a built-in or command backend's run.
std::string CacheKeyOf(const Backend& backend, const RunRequest& request);

// The program a command template starts (its first word) exists: as a path relative to the
// working directory, or on PATH.
bool ProgramAvailable(const Backend& backend);

RunOutcome ObtainRun(const Backend& backend, const RunRequest& request, const RunCache& cache);

}  // namespace owval::backends
