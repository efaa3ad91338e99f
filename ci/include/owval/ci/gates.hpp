#pragma once
// CI gates over an artifact directory (same layout as the checklist, docs/checklist.md):
//  - quick-test: the runs completed: reference and candidate exist, parse, hold no NaN/Inf;
//  - validate: the directory's reference is the caller's, stability of both, incompressibility
//    of the candidate's liquid (when it carries density and has liquid), and frame parity of the
//    candidate against the reference.
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "owval/compare/parity.hpp"

namespace owval::ci {

struct GateResult {
  GateResult() = default;
  GateResult(std::string name, bool pass, std::string detail)
      : name(std::move(name)), pass(pass), detail(std::move(detail)) {}

  std::string name;
  bool pass = false;
  std::string detail;
  // The gate's figures as structured data where it has a report of its own (stability,
  // incompressibility: their ToJson; the parity gate: its gates), else null. --json prints it
  // so that a script reads the numbers instead of parsing `detail`.
  nlohmann::json measured;
};

struct GateReport {
  std::vector<GateResult> gates;
  bool pass() const;  // every gate passes, and there is at least one
  std::string ToText() const;
  // {"pass": bool, "gates": [{"name", "pass", "detail"[, "measured"]}, ...]}: what ToText says,
  // for scripts.
  nlohmann::json ToJson() const;
};

GateReport QuickTest(const std::filesystem::path& directory);
// `caller_reference`: the trajectory the directory's reference must be (frame for frame, within
// 1e-3 cu); empty fails that gate, since the directory's own reference could be its candidate
// under another name and the parity gate would judge the candidate against itself.
GateReport Validate(const std::filesystem::path& directory,
                    const compare::ParityOptions& parity = {},
                    const std::filesystem::path& caller_reference = {});

}  // namespace owval::ci
