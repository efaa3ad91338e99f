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

namespace owval::scenarios {

struct Scenario {
  std::string name;
  std::string description;
  std::string generator;                     // one_sprig | free_fall
  std::map<std::string, double> parameters;  // generator parameters (defaults filled in)
  std::size_t track_particle = 0;
  std::string track_axis = "y";
  std::string predictor;  // harmonic_spring | free_fall
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

// A scenario name or a configuration file path → configuration.
engine::SiberneticConfig ResolveConfig(const std::string& name_or_path,
                                       const std::filesystem::path& data_dir);

// Generators (owval's own code):
// A box of side `box_cu` walled by the shell of a lattice of spacing r0 (inward unit normals in
// the velocity slot, 4th component `normal_w`).
void AddBoxWalls(float box_cu, float r0_cu, float normal_w, engine::SiberneticConfig* config);
// One elastic particle (type 2.1) hanging from the top wall's centre particle by one spring.
engine::SiberneticConfig OneSprig(const std::map<std::string, double>& parameters);
// One liquid particle falling from rest in the walled box.
engine::SiberneticConfig FreeFall(const std::map<std::string, double>& parameters);

}  // namespace owval::scenarios
