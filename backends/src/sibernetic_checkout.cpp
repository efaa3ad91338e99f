#include "owval/backends/sibernetic_checkout.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "owval/base/errors.hpp"
#include "owval/base/json_file.hpp"

namespace owval::backends {
namespace fs = std::filesystem;
namespace {

double Positive(const nlohmann::json& run, const char* key, const fs::path& file) {
  const std::string field = std::string("sibernetic.") + key;
  const double value = NumberField(run, key, file, field);
  if (!(value > 0))
    throw InputError(file.string(), 0, "\"" + field + "\": expected a positive number");
  return value;
}

Scenario FromManifest(const fs::path& file, const fs::path& checkout) {
  const nlohmann::json m = ReadJsonFile(file);
  if (!m.is_object() || !m.contains("sibernetic") || !m["sibernetic"].is_object())
    throw InputError(file.string(), 0, "\"sibernetic\": expected an object");
  const nlohmann::json& run = m["sibernetic"];
  if (!run.contains("configuration") || !run["configuration"].is_string())
    throw InputError(file.string(), 0, "\"sibernetic.configuration\": expected a path string");
  Scenario s;
  s.name = file.stem().string();
  s.directory = file.parent_path();
  s.sibernetic_configuration = run["configuration"];
  s.configuration = checkout / s.sibernetic_configuration;
  s.time_s = Positive(run, "time_s", file);
  s.time_step_s = Positive(run, "time_step_s", file);
  const double log_step = Positive(run, "log_step", file);
  if (log_step != std::floor(log_step) || log_step > 1e9)
    throw InputError(file.string(), 0, "\"sibernetic.log_step\": expected an integer >= 1");
  s.log_step = int(log_step);
  return s;
}

}  // namespace

fs::path SiberneticCheckout(const std::string& flag) {
  if (!flag.empty()) return flag;
  const char* home = std::getenv("SIBERNETIC_HOME");
  return home ? fs::path(home) : fs::path();
}

std::vector<Scenario> SiberneticScenarios(const fs::path& checkout, const fs::path& manifests,
                                          const std::vector<std::string>& names) {
  std::error_code ec;
  if (!fs::is_directory(checkout, ec))
    throw InputError(checkout.string(), 0, "not a directory (a checkout of openworm/sibernetic)");
  std::vector<Scenario> found;
  for (const std::string& name : names) {
    const fs::path file = manifests / (name + ".json");
    if (!fs::is_regular_file(file, ec))
      throw InputError(manifests.string(), 0, "no Sibernetic demo \"" + name + "\"");
    found.push_back(FromManifest(file, checkout));
    if (!fs::is_regular_file(found.back().configuration, ec))
      throw InputError(
          found.back().configuration.string(), 0,
          "not found (is " + checkout.string() + " a checkout of openworm/sibernetic?)");
  }
  if (!names.empty()) return found;
  for (const auto& entry : fs::directory_iterator(manifests, ec)) {
    if (entry.path().extension() != ".json") continue;
    Scenario s = FromManifest(entry.path(), checkout);
    if (fs::is_regular_file(s.configuration, ec)) found.push_back(s);
  }
  std::sort(found.begin(), found.end(),
            [](const Scenario& a, const Scenario& b) { return a.name < b.name; });
  return found;
}

fs::path SiberneticManifestOf(const fs::path& manifests, const std::string& repository_path) {
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(manifests, ec))
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    const nlohmann::json m = ReadJsonFile(file);  // owval's own scenes have no "sibernetic"
    if (!m.is_object() || !m.contains("sibernetic") || !m["sibernetic"].is_object()) continue;
    const nlohmann::json& run = m["sibernetic"];
    if (run.contains("configuration") && run["configuration"] == repository_path) return file;
  }
  return {};
}

}  // namespace owval::backends
