#include "owval/scenarios/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/json_file.hpp"
#include "owval/base/number_text.hpp"
#include "owval/base/one_line.hpp"

namespace owval::scenarios {
namespace fs = std::filesystem;

namespace {
// A whole-number field, range-checked before any conversion: nlohmann's get<int>() of 1e30 is a
// float-to-integer cast with undefined behaviour (found by fuzz/fuzz_manifest.cpp).
std::size_t WholeNumber(const nlohmann::json& object, const char* field, double fallback,
                        double min, double max, const fs::path& path) {
  if (!object.contains(field)) return static_cast<std::size_t>(fallback);
  const nlohmann::json& v = object.at(field);
  const double value = v.is_number() ? v.get<double>() : std::nan("");
  if (!(value >= min && value <= max && value == std::floor(value)))
    throw InputError(path.string(), 0,
                     std::string("bad scenario manifest: ") + field +
                         " must be a whole number from " +
                         std::to_string(static_cast<long long>(min)) + " to " +
                         std::to_string(static_cast<long long>(max)));
  return static_cast<std::size_t>(value);
}

// A scenario is a manifest's file name, never a path: `scenario show ../manifests/one_sprig`
// read a manifest through "..", and `../../tmp/x` any x.json as one (nlohmann's own line then).
// Nor longer than a file name may be (a 300-digit name said "File name too long").
bool IsScenarioName(const std::string& name) {
  return !name.empty() && name.size() <= 200 && name.front() != '.' &&
         name.find_first_of("/\\") == std::string::npos;
}

}  // namespace

Scenario LoadScenario(const std::string& name, const fs::path& data_dir) {
  const fs::path path = data_dir / "scenarios" / "manifests" / (name + ".json");
  std::error_code error;
  if (!IsScenarioName(name) || !fs::exists(path, error)) {
    std::string known;
    for (const auto& n : ListScenarios(data_dir)) known += (known.empty() ? "" : ", ") + n;
    throw InputError(OneLine(name, 60), 0,
                     "no such scenario (built-in: " + known + ") or configuration file");
  }
  nlohmann::json m;
  try {
    m = nlohmann::json::parse(ReadWholeFile(path));
    Scenario s;
    s.name = m.at("name").get<std::string>();
    s.description = m.value("description", "");
    s.generator = m.at("generator").get<std::string>();
    const nlohmann::json parameters = m.value("parameters", nlohmann::json::object());
    for (const auto& [k, v] : parameters.items()) s.parameters[k] = v.get<double>();
    s.track = Track::FromJson(m.value("track", nlohmann::json::object()), path.string());
    s.predictor = m.value("predictor", "");
    s.duration_s = m.value("duration_s", 0.05);
    s.log_step = static_cast<int>(WholeNumber(m, "log_step", 1, 1, 2147483647, path));
    if (m.contains("reference")) s.reference = data_dir / m["reference"].get<std::string>();
    ApplyManifestGates(m.value("gates", nlohmann::json::object()), path.string(), &s.gates);
    if (m.contains("frames")) s.sample_frames = m["frames"].get<std::vector<std::size_t>>();
    s.manifest = m;
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string(), 0, std::string("bad scenario manifest: ") + e.what());
  }
}

void ApplyManifestGates(const nlohmann::json& gates, const std::string& where,
                        compare::ParityGates* out) {
  if (!gates.is_object()) throw InputError(where, 0, "\"gates\": expected an object");
  for (const auto& item : gates.items()) {
    const std::string& key = item.key();
    const nlohmann::json& value = item.value();
    const auto field = std::find_if(
        compare::kGateThresholdFields.begin(), compare::kGateThresholdFields.end(),
        [&key](const compare::GateThresholdField& f) { return key == f.manifest_key; });
    if (field == compare::kGateThresholdFields.end())
      throw InputError(where, 0, "\"gates." + key + "\": unknown gate");
    if (!value.is_number() || !(value.get<double>() > 0) || !std::isfinite(value.get<double>()))
      throw InputError(where, 0, "\"gates." + key + "\": expected a positive number");
    out->*field->member = {value.get<double>(), compare::ThresholdSource::kManifest};
  }
}

void ApplyManifestFile(const fs::path& manifest, compare::ParityOptions* options) {
  const nlohmann::json m = ReadJsonFile(manifest);
  if (!m.is_object()) throw InputError(manifest.string(), 0, "expected a JSON object");
  if (m.contains("track")) options->track = Track::FromJson(m["track"], manifest.string());
  if (m.contains("gates")) ApplyManifestGates(m["gates"], manifest.string(), &options->gates);
}

compare::ParityOptions ParityOptionsFrom(const std::string& scenario, const fs::path& manifest,
                                         const fs::path& data_dir) {
  compare::ParityOptions options;
  if (!scenario.empty()) {
    const Scenario s = LoadScenario(scenario, data_dir);
    options.gates = s.gates;
    options.track = s.track;
  }
  if (!manifest.empty()) ApplyManifestFile(manifest, &options);
  return options;
}

std::vector<std::string> ListScenarios(const fs::path& data_dir) {
  std::vector<std::string> names;
  const fs::path dir = data_dir / "scenarios" / "manifests";
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

engine::SiberneticConfig GenerateConfig(const Scenario& s,
                                        const std::map<std::string, double>& overrides) {
  std::map<std::string, double> p = s.parameters;
  for (const auto& [k, v] : overrides) p[k] = v;
  engine::SiberneticConfig c = Generate(s.generator, p);
  c.source = "scenario " + s.name;
  return c;
}

engine::SiberneticConfig GenerateConfigFile(const Scenario& s,
                                            const std::map<std::string, double>& overrides,
                                            const std::filesystem::path& out) {
  CheckOutputPath(out);
  const engine::SiberneticConfig config = GenerateConfig(s, overrides);
  engine::WriteSiberneticConfig(config, out);
  return config;
}

std::map<std::string, double> ParseOverrides(const std::vector<std::string>& assignments) {
  std::map<std::string, double> out;
  for (const auto& [name, value] : ParseAssignments(assignments, "--param")) out[name] = value;
  return out;
}

engine::SiberneticConfig ResolveConfig(const std::string& name_or_path, const fs::path& data_dir) {
  return ResolveScenario(name_or_path, {}, data_dir).config;
}

ResolvedScenario ResolveScenario(const std::string& name_or_path,
                                 const std::vector<std::string>& overrides,
                                 const fs::path& data_dir) {
  std::error_code error;  // a name too long for a file is no file
  if (fs::exists(name_or_path, error) && !fs::is_directory(name_or_path, error)) {
    if (!overrides.empty())
      throw InputError("--param applies to a scenario's generator, not to a configuration file");
    return {engine::ReadSiberneticConfig(name_or_path), fs::path(name_or_path).filename().string(),
            ""};
  }
  const Scenario scenario = LoadScenario(name_or_path, data_dir);
  return {GenerateConfig(scenario, ParseOverrides(overrides)), scenario.name, scenario.predictor};
}

}  // namespace owval::scenarios
