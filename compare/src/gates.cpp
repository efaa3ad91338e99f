#include "owval/compare/gates.hpp"
#include "owval/base/format.hpp"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace owval::compare {
namespace {

// A Markdown table cell: a '|' would end the cell.
std::string Cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string ValueText(const Gate& g) {
  if (g.status == GateStatus::kNotApplicable && !std::isfinite(g.value)) return "-";
  return FormatNumber(g.value, 4);
}

}  // namespace

const char* SourceName(ThresholdSource s) {
  switch (s) {
    case ThresholdSource::kDefault:
      return "default";
    case ThresholdSource::kManifest:
      return "manifest";
    case ThresholdSource::kFlag:
      return "flag";
  }
  return "?";
}

const char* StatusName(GateStatus s) {
  switch (s) {
    case GateStatus::kPass:
      return "pass";
    case GateStatus::kFail:
      return "FAIL";
    case GateStatus::kNotApplicable:
      return "n/a";
  }
  return "?";
}

Gate MakeGate(std::string name, std::string measures, double value, Threshold threshold,
              std::string unit) {
  Gate g;
  g.name = std::move(name);
  g.measures = std::move(measures);
  g.value = value;
  g.threshold = threshold;
  g.unit = std::move(unit);
  return g;
}

void Decide(Gate* g) {
  g->status = std::isfinite(g->value) && g->value < g->threshold.value ? GateStatus::kPass
                                                                       : GateStatus::kFail;
}

std::string FailedGateNames(const std::vector<Gate>& gates) {
  std::string names;
  for (const Gate& g : gates)
    if (g.status == GateStatus::kFail) names += (names.empty() ? "" : ", ") + g.name;
  return names;
}

bool AllApplicablePass(const std::vector<Gate>& gates) {
  bool any = false;
  for (const Gate& g : gates) {
    if (g.status == GateStatus::kFail) return false;
    any = any || g.status == GateStatus::kPass;
  }
  return any;
}

nlohmann::json ToJson(const Gate& g) {
  return {{"name", g.name},
          {"measures", g.measures},
          {"value", std::isfinite(g.value) ? nlohmann::json(g.value) : nlohmann::json(nullptr)},
          {"threshold", g.threshold.value},
          {"threshold_source", SourceName(g.threshold.source)},
          {"unit", g.unit},
          {"status", StatusName(g.status)},
          {"detail", g.detail}};
}

nlohmann::json ToJson(const std::vector<Gate>& gates) {
  nlohmann::json list = nlohmann::json::array();
  for (const Gate& g : gates) list.push_back(ToJson(g));
  return list;
}

std::string GatesMarkdownTable(const std::vector<Gate>& gates) {
  std::ostringstream s;
  s << "| gate | measures | value | threshold | source | result |\n|---|---|---|---|---|---|\n";
  for (const Gate& g : gates)
    s << "| `" << g.name << "` | " << Cell(g.measures) << " | " << ValueText(g) << " | < "
      << FormatNumber(g.threshold.value, 4) << " " << g.unit << " | "
      << SourceName(g.threshold.source) << " | "
      << (g.status == GateStatus::kFail ? "**FAIL**" : StatusName(g.status))
      << Cell(g.detail.empty() ? "" : ": " + g.detail) << " |\n";
  return s.str();
}

std::string GatesTextTable(const std::vector<Gate>& gates) {
  std::ostringstream s;
  char line[512];
  std::snprintf(line, sizeof line, "  %-28s %-5s %-11s %-12s %-9s %s\n", "gate", "", "value",
                "threshold", "source", "unit; detail");
  s << line;
  for (const Gate& g : gates) {
    std::snprintf(line, sizeof line, "  %-28s %-5s %-11s < %-10s %-9s %s%s%s\n", g.name.c_str(),
                  StatusName(g.status), ValueText(g).c_str(),
                  FormatNumber(g.threshold.value, 4).c_str(), SourceName(g.threshold.source),
                  g.unit.c_str(), g.detail.empty() ? "" : "; ", g.detail.c_str());
    s << line;
  }
  return s.str();
}

}  // namespace owval::compare
