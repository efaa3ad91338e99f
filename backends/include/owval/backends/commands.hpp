#pragma once
// `owval compare A B` and `owval bench backends A B ...` as library calls: backends named as a
// user names them, the registry and the run cache as --backends, --cache and --no-cache select
// them, and every output path checked before the first run starts.
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/backends/bench.hpp"
#include "owval/backends/cache.hpp"
#include "owval/backends/registry.hpp"
#include "owval/backends/suite.hpp"
#include "owval/compare/parity.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/track_choice.hpp"

namespace owval::backends {

// "NAME=VALUE" strings (values of {set:NAME}) as a map; InputError naming --set otherwise, or
// naming NAME when it is given twice.
std::map<std::string, std::string> ParseSets(const std::vector<std::string>& sets);

// Which registry file and run cache a command uses.
struct BackendSelection {
  std::string file;       // --backends ("": ./owval-backends.json, else $XDG_CONFIG_HOME/owval)
  CacheOptions cache;     // --cache DIR, --no-cache
  Registry Load() const;  // LoadRegistry, from the process environment
};

struct CompareRequest {
  std::string reference, candidate;  // two trajectory files, or two backend names
  std::string markdown;              // also write the report here ("": no)
  // Two files: their parity, with the manifest's track and gates under what the flags give.
  std::string manifest;
  TrackChoice track;
  std::string frames;                             // "0,15,100,200" ("": every paired frame)
  std::optional<double> scale;                    // cu
  std::vector<std::optional<double>> thresholds;  // by compare::kGateThresholdFields' order
  TextReadOptions reading;
  // Two names: every selected scenario, run or fetched on both sides.
  BackendSelection backends;
  ScenarioSelection scenarios;
  std::vector<std::string> sets;                        // NAME=VALUE
  std::function<void(const std::string&)> on_progress;  // may be empty
};

struct CompareOutcome {
  std::optional<compare::ParityReport> files;  // two trajectory files
  std::optional<SuiteReport> suite;            // two backend names
  // What the caller should know that the report does not say (one printable line each): two
  // files whose reference is a store folder's run judged without the manifest the named form
  // judges that run by.
  std::vector<std::string> notes;
  bool pass() const;
  nlohmann::json ToJson() const;
  std::string ToTable() const;
  std::string ToMarkdown() const;
};

// InputError before anything is read when one argument is a file and the other is not (named:
// missing, a directory, not a regular file), a name with a '/' is no file, or --markdown is
// unwritable or one of the inputs, or when a field of the other form is set (files: scenarios,
// sets, backends file, cache; names: manifest, track, frames, scale, thresholds), which that form
// would ignore. Writes request.markdown when given.
CompareOutcome CompareNamed(const CompareRequest& request);

struct BenchRequest {
  std::vector<std::string> names;       // backends; ratios are to the first
  std::string scenario;                 // a folder name under reference_dir
  std::filesystem::path reference_dir;  // the scenario folders
  std::string json, markdown;           // also write the JSON, the Markdown table here
  double time_s = 0;                    // simulated seconds (0: the scenario's)
  BenchOptions options;                 // repeat, threads, on_progress
  std::vector<std::string> sets;        // NAME=VALUE
  BackendSelection backends;
};

// Checks the outputs (never one of the timed scenario's own files or the backends file: `--json
// ../shared/reference/demo1/meta.json` would replace the scenario it times), times the backends
// and writes request.json and request.markdown.
BenchReport BenchNamed(const BenchRequest& request);

}  // namespace owval::backends
