#include "owval/backends/scenario_store.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <regex>

#include "owval/base/errors.hpp"
#include "owval/base/json_file.hpp"

namespace owval::backends {
namespace fs = std::filesystem;

namespace {

// Sibernetic's timelimit= in the recorded command. std::stod threw its bare "stod" for
// "timelimit=." and "timelimit=1e999" (the whole message); strtod and a check name the field.
double Timelimit(const std::string& text, const fs::path& file) {
  char* end = nullptr;
  const double seconds = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(seconds) || !(seconds > 0))
    throw InputError(file.string(), 0,
                     "\"command\": timelimit=" + text + ": expected a positive finite number");
  return seconds;
}

double TimeOf(const nlohmann::json& meta, double dt, int log_step, const fs::path& file) {
  if (meta.contains("timelimit_s")) return NumberField(meta, "timelimit_s", file);
  if (meta.contains("command") && meta["command"].is_string()) {
    std::smatch m;
    const std::string command = meta["command"];
    if (std::regex_search(command, m, std::regex(R"(timelimit=([0-9.eE+-]+))")))
      return Timelimit(m[1], file);
  }
  if (meta.contains("frames")) return NumberField(meta, "frames", file) * log_step * dt;
  throw InputError(file.string(), 0, "no time: expected timelimit_s, timelimit= or frames");
}

// meta.json's configuration.repo_path; "" when "configuration" is a description or absent.
std::string RepositoryPath(const nlohmann::json& meta, const fs::path& file) {
  if (!meta.contains("configuration") || !meta["configuration"].is_object()) return "";
  const nlohmann::json& configuration = meta["configuration"];
  if (!configuration.contains("repo_path")) return "";
  if (!configuration["repo_path"].is_string() || configuration["repo_path"] == "")
    throw InputError(file.string(), 0, "\"configuration.repo_path\": expected a path string");
  return configuration["repo_path"];
}

}  // namespace

Scenario ReadScenario(const fs::path& directory) {
  const fs::path file = directory / "meta.json";
  const nlohmann::json meta = ReadJsonFile(file);
  Scenario s;
  s.name = directory.filename().string();
  s.directory = directory;
  std::error_code ec;
  if (fs::is_regular_file(directory / "configuration", ec))
    s.configuration = directory / "configuration";
  s.time_step_s = NumberField(meta, "time_step_s", file);
  const double log_step = NumberField(meta, "log_step", file);
  // Checked against int's range before the cast: a log_step of 1e300 became INT_MIN (UB).
  if (!(s.time_step_s > 0) || !(log_step >= 1) || log_step != std::floor(log_step) ||
      log_step > std::numeric_limits<int>::max())
    throw InputError(file.string(), 0,
                     "time_step_s > 0 and integer log_step from 1 to 2^31-1 expected");
  s.log_step = static_cast<int>(log_step);
  s.time_s = TimeOf(meta, s.time_step_s, s.log_step, file);
  if (!(s.time_s > 0) || !std::isfinite(s.time_s))
    throw InputError(file.string(), 0, "time: expected a positive finite number of seconds");
  if (meta.contains("wall_s")) s.recorded_wall_s = NumberField(meta, "wall_s", file);
  if (meta.contains("wall_includes") && meta["wall_includes"].is_string())
    s.recorded_wall_includes = meta["wall_includes"];
  s.sibernetic_configuration = RepositoryPath(meta, file);
  return s;
}

std::vector<Scenario> FindScenarios(const fs::path& root, const std::vector<std::string>& names) {
  std::error_code ec;
  if (!fs::is_directory(root, ec)) throw InputError(root.string(), 0, "not a scenario directory");
  std::vector<Scenario> found;
  for (const std::string& name : names) {
    if (!fs::is_regular_file(root / name / "meta.json", ec))
      throw InputError(root.string(), 0,
                       "no scenario \"" + name + "\" (no " + name + "/meta.json)");
    found.push_back(ReadScenario(root / name));
    if (found.back().configuration.empty())
      throw InputError((root / name).string(), 0, "no configuration file");
  }
  if (!names.empty()) return found;
  for (const auto& entry : fs::directory_iterator(root)) {
    const fs::path dir = entry.path();
    if (fs::is_regular_file(dir / "configuration", ec) &&
        fs::is_regular_file(dir / "meta.json", ec))
      found.push_back(ReadScenario(dir));
  }
  std::sort(found.begin(), found.end(),
            [](const Scenario& a, const Scenario& b) { return a.name < b.name; });
  return found;
}

fs::path RecordedTrajectory(const fs::path& directory) {
  std::error_code ec;
  for (const char* name : {"position_buffer.txt", "position_buffer.txt.gz", "trajectory.h5"})
    if (fs::is_regular_file(directory / name, ec)) return directory / name;
  return {};
}

}  // namespace owval::backends
