#pragma once
// Built-in scenarios: a manifest (scenarios/manifests/NAME.json) names a generator and its
// parameters, what to track, which predictor applies, the gate thresholds and, when one exists,
// a bundled reference trajectory. Generators are owval's own code and write Sibernetic's format.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/compare/parity.hpp"
#include "owval/engine/config.hpp"
#include "owval/scenarios/generators.hpp"
#include "owval/trajectory/track.hpp"

namespace owval::scenarios {

struct Scenario {
  std::string name;
  std::string description;
  std::string generator;  // one_sprig | free_fall | hanging_chain | liquid_column
  std::map<std::string, double> parameters;  // generator parameters (defaults filled in)
  Track track;  // the tracked quantity of every phase (reconcile, fit, render, frame gate)
  std::string predictor;  // harmonic_spring | free_fall | hanging_chain | hydrostatic_column
  double duration_s = 0.05;
  int log_step = 1;
  std::filesystem::path reference;  // bundled reference trajectory ("" if none)
  // Reference frames the labelled PNGs show (manifest "frames"; clamped to the run's length).
  std::vector<std::size_t> sample_frames = {0, 15, 100, 200};
  compare::ParityGates gates;  // the manifest's "gates" over the defaults (ApplyManifestGates)
  nlohmann::json manifest;     // the manifest as read
};

// The manifest's "gates" object onto `gates` (source: manifest). Keys: the manifest_key of
// compare::kGateThresholdFields, each a positive number. InputError naming `where` and the key
// for anything else.
void ApplyManifestGates(const nlohmann::json& gates, const std::string& where,
                        compare::ParityGates* out);

// A manifest file's "track" and "gates" onto parity options (owval compare --manifest).
void ApplyManifestFile(const std::filesystem::path& manifest, compare::ParityOptions* options);

// A built-in scenario's track and gates (by name), else a manifest file's, over the defaults
// (both empty: the defaults): what `owval checklist --scenario|--manifest` applies.
compare::ParityOptions ParityOptionsFrom(const std::string& scenario,
                                         const std::filesystem::path& manifest,
                                         const std::filesystem::path& data_dir);

// Reads data_dir/scenarios/manifests/NAME.json; InputError for an unknown name or bad manifest.
Scenario LoadScenario(const std::string& name, const std::filesystem::path& data_dir);
std::vector<std::string> ListScenarios(const std::filesystem::path& data_dir);

// The configuration a generator builds from the scenario's parameters (overrides applied first).
engine::SiberneticConfig GenerateConfig(const Scenario& scenario,
                                        const std::map<std::string, double>& overrides = {});

// `owval scenario generate`: that configuration written to `out` in Sibernetic's format, `out`
// checked before the lattice is made (a directory failed only at the rename). Returns it.
engine::SiberneticConfig GenerateConfigFile(const Scenario& scenario,
                                            const std::map<std::string, double>& overrides,
                                            const std::filesystem::path& out);

// "NAME=NUMBER" strings (the --param options) → generator parameter overrides, read by
// ParseAssignments (base/number_text.hpp): InputError on anything else or a NAME given twice.
std::map<std::string, double> ParseOverrides(const std::vector<std::string>& assignments);

// A scenario name or a configuration file path → configuration.
engine::SiberneticConfig ResolveConfig(const std::string& name_or_path,
                                       const std::filesystem::path& data_dir);

// The same, with what a scenario adds: its name (a file's: the file name), its predictor ("" for
// a file) and generator parameter overrides ("NAME=NUMBER"; InputError on a file, which has no
// generator).
struct ResolvedScenario {
  engine::SiberneticConfig config;
  std::string name, predictor;
};
ResolvedScenario ResolveScenario(const std::string& name_or_path,
                                 const std::vector<std::string>& overrides,
                                 const std::filesystem::path& data_dir);

}  // namespace owval::scenarios
