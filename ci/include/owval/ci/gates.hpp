#pragma once
// CI gates over an artifact directory (same layout as the checklist, docs/checklist.md):
//  - quick-test: the runs completed: reference and candidate exist, parse, hold no NaN/Inf;
//  - validate: stability of both, incompressibility of the candidate's liquid (when it carries
//    density and has liquid), and frame parity of the candidate against the reference.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "owval/compare/parity.hpp"

namespace owval::ci {

struct GateResult {
  std::string name;
  bool pass = false;
  std::string detail;
};

struct GateReport {
  std::vector<GateResult> gates;
  bool pass() const;
  std::string ToText() const;
};

GateReport QuickTest(const std::filesystem::path& directory);
GateReport Validate(const std::filesystem::path& directory,
                    const compare::ParityOptions& parity = {});

}  // namespace owval::ci
