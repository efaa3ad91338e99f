#include "owval/backends/suite.hpp"

#include <chrono>
#include <cstdio>

#include "owval/backends/scenario_store.hpp"
#include "owval/backends/sibernetic_checkout.hpp"
#include "owval/base/errors.hpp"
#include "owval/scenarios/scenario.hpp"

namespace owval::backends {
namespace fs = std::filesystem;

namespace {

compare::ParityOptions OptionsFor(const Scenario& s,
                                  const std::vector<fs::path>& manifest_directories) {
  compare::ParityOptions o;
  o.track = Track{};  // particle 0, y
  if (const fs::path manifest = ScenarioManifest(s, manifest_directories); !manifest.empty())
    scenarios::ApplyManifestFile(manifest, &o);
  return o;
}

SideOutcome Side(const RunOutcome& o) { return {o.source, o.detail, o.wall_s}; }

std::string Fixed(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

fs::path ScenarioManifest(const Scenario& s, const std::vector<fs::path>& manifest_directories) {
  std::error_code ec;
  if (const fs::path own = s.directory / "manifest.json"; fs::is_regular_file(own, ec)) return own;
  for (const fs::path& directory : manifest_directories)
    if (const fs::path named = directory / (s.name + ".json"); fs::is_regular_file(named, ec))
      return named;
  if (s.sibernetic_configuration.empty()) return {};
  for (const fs::path& directory : manifest_directories)
    if (const fs::path same = SiberneticManifestOf(directory, s.sibernetic_configuration);
        !same.empty())
      return same;
  return {};
}

bool SuiteReport::pass() const {
  for (const ScenarioParity& s : scenarios)
    if (!s.report.pass()) return false;
  return true;
}

std::string SuiteReport::FailedGates() const {
  std::string failed;
  for (const ScenarioParity& s : scenarios)
    if (!s.report.pass())
      failed += (failed.empty() ? "" : "; ") + s.scenario + ": " + s.report.FailedGates();
  return failed;
}

std::string SuiteReport::ToTable() const {
  std::string t = "parity of " + b + " against " + a + "\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-16s %-30s %12s %10s  %s\n", "scenario", "gate", "value",
                "threshold", "pass");
  t += line;
  for (const ScenarioParity& s : scenarios)
    for (const compare::Gate& g : s.report.gates) {
      std::snprintf(line, sizeof line, "%-16s %-30s %12.4g %10.4g  %s\n", s.scenario.c_str(),
                    g.name.c_str(), g.value, g.threshold.value, compare::StatusName(g.status));
      t += line;
    }
  t += "runs:\n";
  for (const ScenarioParity& s : scenarios)
    for (const auto& [name, side] : {std::pair{a, s.a}, std::pair{b, s.b}})
      t += "  " + s.scenario + " " + name + ": " + side.source +
           (side.source == "ran" ? " (" + Fixed("%.1f", side.wall_s) + " s)" : "") + ", " +
           side.detail + "\n";
  t += pass() ? "all gates pass (" + Fixed("%.1f", wall_s) + " s)\n"
              : "FAILED: " + FailedGates() + "\n";
  return t;
}

std::string SuiteReport::ToMarkdown() const {
  std::string m = "# Parity of `" + b + "` against `" + a + "`\n\n";
  m += "| scenario | gate | value | threshold | pass |\n|---|---|---|---|---|\n";
  for (const ScenarioParity& s : scenarios)
    for (const compare::Gate& g : s.report.gates)
      m += "| " + s.scenario + " | " + g.name + " | " + Fixed("%.4g", g.value) + " | " +
           Fixed("%.4g", g.threshold.value) + " | " + compare::StatusName(g.status) + " |\n";
  m += "\n| scenario | " + a + " | " + b + " |\n|---|---|---|\n";
  for (const ScenarioParity& s : scenarios)
    m += "| " + s.scenario + " | " + s.a.source + " | " + s.b.source + " |\n";
  m += pass() ? "\nAll gates pass.\n" : "\nFailed: " + FailedGates() + "\n";
  return m;
}

nlohmann::json SuiteReport::ToJson() const {
  nlohmann::json j = {{"a", a}, {"b", b}, {"pass", pass()}, {"wall_s", wall_s}};
  j["scenarios"] = nlohmann::json::array();
  for (const ScenarioParity& s : scenarios) {
    nlohmann::json runs;
    for (const auto& [name, side] :
         {std::pair{std::string("a"), s.a}, std::pair{std::string("b"), s.b}})
      runs[name] = {{"source", side.source}, {"detail", side.detail}, {"wall_s", side.wall_s}};
    j["scenarios"].push_back({{"scenario", s.scenario},
                              {"pass", s.report.pass()},
                              {"runs", runs},
                              {"report", s.report.ToJson()}});
  }
  if (!pass()) j["failed"] = FailedGates();
  return j;
}

SuiteReport CompareBackends(const Backend& a, const Backend& b, const SuiteOptions& options,
                            const RunCache& cache) {
  const auto start = std::chrono::steady_clock::now();
  SuiteReport report;
  report.a = a.name;
  report.b = b.name;
  for (const Scenario& s : options.scenarios) {
    const compare::ParityOptions parity = OptionsFor(s, options.manifest_directories);
    RunRequest request;
    request.scenario = s;
    request.sets = options.sets;
    if (options.on_progress) options.on_progress(s.name + ": " + a.name);
    const RunOutcome ra = ObtainRun(a, request, cache);
    if (options.on_progress) options.on_progress(s.name + ": " + b.name);
    const RunOutcome rb = ObtainRun(b, request, cache);
    const std::unique_ptr<FrameSource> frames_a = ra.Frames(), frames_b = rb.Frames();
    report.scenarios.push_back(
        {s.name, Side(ra), Side(rb), compare::CompareFrameSources(*frames_a, *frames_b, parity)});
  }
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace owval::backends

namespace owval::backends {

std::filesystem::path DefaultScenarioRoot(const Backend& a, const Backend& b,
                                          const std::filesystem::path& fallback) {
  for (const Backend* x : {&a, &b})
    if (!x->store.empty()) return x->store;
  return fallback;
}

std::vector<std::filesystem::path> StoreManifestDirectories(const std::filesystem::path& data_dir) {
  return {data_dir / "scenarios" / "sibernetic", data_dir / "scenarios" / "manifests"};
}

void SelectScenarios(const Backend& a, const Backend& b, const ScenarioSelection& selection,
                     SuiteOptions* options) {
  const std::filesystem::path checkout = SiberneticCheckout(selection.sibernetic);
  const std::filesystem::path demos = selection.data_dir / "scenarios" / "sibernetic";
  if (!checkout.empty() && selection.reference_dir.empty()) {
    options->manifest_directories = {demos};
    options->scenarios = SiberneticScenarios(checkout, demos, selection.names);
  } else {
    const std::filesystem::path root = selection.reference_dir.empty()
                                           ? DefaultScenarioRoot(a, b, selection.shared_reference)
                                           : selection.reference_dir;
    options->scenarios = FindScenarios(root, selection.names);
    options->manifest_directories = StoreManifestDirectories(selection.data_dir);
  }
  if (options->scenarios.empty())
    throw InputError("no scenario with a configuration to compare on");
}

}  // namespace owval::backends
