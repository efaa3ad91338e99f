#pragma once
// Parity of two backends over a set of scenarios (owval compare A B with names): each scenario
// is run or fetched on both sides (runner.hpp) and compared by compare::CompareTrajectories with
// the scenario's manifest (manifest.json in the scenario folder, else the first NAME.json in
// manifest_directories, else the first Sibernetic manifest there naming the folder's
// configuration.repo_path: track and gates) or, without one, particle 0's y and the default
// gates.
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/backends/runner.hpp"
#include "owval/compare/parity.hpp"

namespace owval::backends {

struct SuiteOptions {
  std::vector<Scenario> scenarios;
  std::vector<std::filesystem::path> manifest_directories;  // NAME.json manifests, in order
  std::map<std::string, std::string> sets;                  // {set:NAME} values
  std::function<void(const std::string&)> on_progress;      // one line per step; may be empty
};

struct SideOutcome {
  std::string source, detail;
  double wall_s = 0;
};

struct ScenarioParity {
  std::string scenario;
  SideOutcome a, b;
  compare::ParityReport report;
};

struct SuiteReport {
  std::string a, b;
  std::vector<ScenarioParity> scenarios;
  double wall_s = 0;
  bool pass() const;
  // "scenario: gate, gate; scenario: gate" for every failed gate ("" when all pass).
  std::string FailedGates() const;
  std::string ToTable() const;  // scenario x gate: value, threshold, pass; then run sources
  std::string ToMarkdown() const;
  nlohmann::json ToJson() const;
};

// The manifest `s` is judged by (the order above), or "" when none applies.
std::filesystem::path ScenarioManifest(
    const Scenario& s, const std::vector<std::filesystem::path>& manifest_directories);

// A is the reference side. InputError for bad input (backend failure, unreadable runs).
SuiteReport CompareBackends(const Backend& a, const Backend& b, const SuiteOptions& options,
                            const RunCache& cache);

}  // namespace owval::backends

namespace owval::backends {

// Where scenarios come from when not given: the store of A, else of B (a command backend's
// fallback store counts), else `fallback`.
std::filesystem::path DefaultScenarioRoot(const Backend& a, const Backend& b,
                                          const std::filesystem::path& fallback);

// Where `owval compare A B` takes its scenarios from.
struct ScenarioSelection {
  std::vector<std::string> names;          // only these scenarios (empty: every one found)
  std::string sibernetic;                  // a Sibernetic checkout (empty: $SIBERNETIC_HOME)
  std::filesystem::path reference_dir;     // scenario folders (empty: DefaultScenarioRoot)
  std::filesystem::path shared_reference;  // DefaultScenarioRoot's fallback
  std::filesystem::path data_dir;  // owval's data: scenarios/manifests, scenarios/sibernetic
};

// Where a store's scenarios find their manifests: data_dir's scenarios/sibernetic (Sibernetic's
// demos), then scenarios/manifests (owval's own scenes).
std::vector<std::filesystem::path> StoreManifestDirectories(const std::filesystem::path& data_dir);

// Sets options->scenarios and manifest_directories: Sibernetic's demos from a checkout when there
// is one and no reference_dir was given, else the scenario folders. InputError when none is found.
// A demo is judged by scenarios/sibernetic/NAME.json's track and gates either way: a store's
// folder named test_gravity is the run of Sibernetic's test_gravity (its meta.json says so), and
// was judged on particle 0 with DD001's defaults, which a 4% error in gravity passed. A folder with
// no Sibernetic demo's name takes scenarios/manifests/NAME.json (a store of owval's own scenes).
void SelectScenarios(const Backend& a, const Backend& b, const ScenarioSelection& selection,
                     SuiteOptions* options);

}  // namespace owval::backends
