#pragma once
// Built-in scenarios: a manifest (scenarios/manifests/NAME.json) names a generator and its
// parameters, what to track, which predictor applies, the gate thresholds and, when one exists,
// a bundled reference trajectory. Generators are owval's own code and write Sibernetic's format.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/scenarios/generators.hpp"

namespace owval::scenarios {

struct Scenario {
  std::string name;
  std::string description;
  std::string generator;  // one_sprig | free_fall | hanging_chain | liquid_column
  std::map<std::string, double> parameters;  // generator parameters (defaults filled in)
  std::size_t track_particle = 0;            // tracked particle (ignored when track_group is set)
  std::string track_group;  // "elastic" | "liquid" | "all": track the group centroid
  std::string track_axis = "y";
  std::string predictor;  // harmonic_spring | free_fall | hanging_chain | hydrostatic_column
  double duration_s = 0.05;
  int log_step = 1;
  std::filesystem::path reference;  // bundled reference trajectory ("" if none)
  nlohmann::json gates;             // thresholds for compare (see cli/cmd_compare.cpp)
  nlohmann::json manifest;          // the manifest as read
};

// Reads data_dir/scenarios/manifests/NAME.json; InputError for an unknown name or bad manifest.
Scenario LoadScenario(const std::string& name, const std::filesystem::path& data_dir);
std::vector<std::string> ListScenarios(const std::filesystem::path& data_dir);

// The configuration a generator builds from the scenario's parameters (overrides applied first).
engine::SiberneticConfig GenerateConfig(const Scenario& scenario,
                                        const std::map<std::string, double>& overrides = {});

// "NAME=NUMBER" strings (the --param options) → generator parameter overrides; InputError on
// anything else.
std::map<std::string, double> ParseOverrides(const std::vector<std::string>& assignments);

// A scenario name or a configuration file path → configuration.
engine::SiberneticConfig ResolveConfig(const std::string& name_or_path,
                                       const std::filesystem::path& data_dir);

}  // namespace owval::scenarios
