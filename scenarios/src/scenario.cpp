#include "owval/scenarios/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"

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
}  // namespace

Scenario LoadScenario(const std::string& name, const fs::path& data_dir) {
  const fs::path path = data_dir / "scenarios" / "manifests" / (name + ".json");
  if (!fs::exists(path)) {
    std::string known;
    for (const auto& n : ListScenarios(data_dir)) known += (known.empty() ? "" : ", ") + n;
    throw InputError(name, 0, "no such scenario (built-in: " + known + ") or configuration file");
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
    const auto track = m.value("track", nlohmann::json::object());
    s.track_particle = WholeNumber(track, "particle", 0, 0, 1e15, path);
    s.track_axis = track.value("axis", std::string("y"));
    s.track_group = track.value("group", std::string());
    s.predictor = m.value("predictor", "");
    s.duration_s = m.value("duration_s", 0.05);
    s.log_step = static_cast<int>(WholeNumber(m, "log_step", 1, 1, 2147483647, path));
    if (m.contains("reference")) s.reference = data_dir / m["reference"].get<std::string>();
    s.gates = m.value("gates", nlohmann::json::object());
    s.manifest = m;
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string(), 0, std::string("bad scenario manifest: ") + e.what());
  }
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

std::map<std::string, double> ParseOverrides(const std::vector<std::string>& assignments) {
  std::map<std::string, double> out;
  for (const std::string& a : assignments) {
    const auto eq = a.find('=');
    try {
      if (eq == std::string::npos) throw std::invalid_argument(a);
      std::size_t used = 0;
      const std::string number = a.substr(eq + 1);
      out[a.substr(0, eq)] = std::stod(number, &used);
      if (used != number.size()) throw std::invalid_argument(a);
    } catch (const std::exception&) {
      throw InputError("--param " + a + ": expected NAME=NUMBER");
    }
  }
  return out;
}

engine::SiberneticConfig ResolveConfig(const std::string& name_or_path, const fs::path& data_dir) {
  if (fs::exists(name_or_path) && !fs::is_directory(name_or_path))
    return engine::ReadSiberneticConfig(name_or_path);
  return GenerateConfig(LoadScenario(name_or_path, data_dir));
}

}  // namespace owval::scenarios
