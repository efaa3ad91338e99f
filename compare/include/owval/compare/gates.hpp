#pragma once
// Gates: a measured value against a threshold, with where the threshold came from and whether
// the gate applies at all. Every verdict owval prints (compare, frames, ci validate, checklist)
// is a list of these, so a FAIL always names the gate, its value and its threshold.
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace owval::compare {

// In order of precedence: a flag overrides a manifest, which overrides the default.
enum class ThresholdSource { kDefault, kManifest, kFlag };
const char* SourceName(ThresholdSource source);  // "default" | "manifest" | "flag"

struct Threshold {
  double value = 0;
  ThresholdSource source = ThresholdSource::kDefault;
};

enum class GateStatus { kPass, kFail, kNotApplicable };
const char* StatusName(GateStatus status);  // "pass" | "FAIL" | "n/a"

struct Gate {
  std::string name;      // stable identifier, e.g. "frames", "elastic.final_distance"
  std::string measures;  // what the value is, in words
  double value = 0;      // the measured value (same unit as the threshold)
  Threshold threshold;   // the gate passes when value < threshold
  std::string unit;      // unit of value and threshold, e.g. "of the reference range"
  GateStatus status = GateStatus::kNotApplicable;
  std::string detail;  // why it failed, or why it does not apply, or what was counted
};

// A gate not yet decided (status n/a, no detail).
Gate MakeGate(std::string name, std::string measures, double value, Threshold threshold,
              std::string unit);

// Sets `gate.status` from value < threshold (a non-finite value fails).
void Decide(Gate* gate);

// The gates that failed, by name ("frames, period"); empty when none did.
std::string FailedGateNames(const std::vector<Gate>& gates);
// True when no applicable gate failed and at least one applied.
bool AllApplicablePass(const std::vector<Gate>& gates);

nlohmann::json ToJson(const Gate& gate);
// The gates as a JSON array, in order (each as ToJson(gate)).
nlohmann::json ToJson(const std::vector<Gate>& gates);
// Rows "gate | measures | value | threshold | source | result" as Markdown.
std::string GatesMarkdownTable(const std::vector<Gate>& gates);
// Aligned plain-text rows for a terminal.
std::string GatesTextTable(const std::vector<Gate>& gates);

}  // namespace owval::compare
