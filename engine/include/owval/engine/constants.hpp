#pragma once
// The one table of the engine's physics constants: every field of PhysicsConstants with its
// name, unit, meaning, the name Sibernetic's [physical parameters] block gives it, and the rule a
// value must satisfy. `owval run --set`, `owval predict --set`, the fit's parameters, the
// [physical parameters] block and a run's provenance all go through it, so a constant is named
// and checked the same way everywhere.
//
// Values are doubles here; the engine rounds each to float as Sibernetic's host does
// (kernels/sph_constants.hpp), so the rules are checked on the float a value becomes: 1e-50 kg is
// a zero mass, 1e39 an infinite one.
#include <span>
#include <string>
#include <vector>

#include "owval/engine/config.hpp"

namespace owval::engine {

enum class ConstantRule {
  kFinite,             // any finite number (gravity components)
  kPositive,           // finite and > 0 (time step, mass, rest density, h, r0, scale)
  kNonNegative,        // finite and >= 0 (stiffnesses, coefficients, delta)
  kIntegerAtLeastOne,  // a whole number in [1, 1000] (iteration counts)
  kSwitch,             // 0 or 1
  kFraction,           // a number in [0, 1]
  kCount,              // a whole number in [0, 1000] (0: derived, e.g. XPBD's substeps)
  kOpenFraction,       // a number in (0, 1) (budgets that divide)
};

struct ConstantInfo {
  const char* name;             // owval's name: --set NAME=VALUE, fit parameters, provenance
  const char* sibernetic_name;  // its name in a [physical parameters] block, or nullptr
  const char* unit;             // "kg", "m/s^2", "cu" (configuration units), "1", ...
  const char* doc;              // one line: what it is and where Sibernetic uses it
  ConstantRule rule;
  const char* scheme;  // nullptr: Sibernetic's physics, used by every scheme; else the one scheme
  double (*get)(const PhysicsConstants&);
  void (*set)(PhysicsConstants&, double);
};

// Every constant, in PhysicsConstants' field order.
std::span<const ConstantInfo> PhysicsConstantTable();

// The entry named `name` (owval's name), or nullptr.
const ConstantInfo* FindConstant(const std::string& name);

// "" when value satisfies the constant's rule, else what was expected ("a finite number > 0").
std::string CheckConstant(const ConstantInfo& constant, double value);

// Sets the constant named `name`. Throws InputError for an unknown name (listing the known ones)
// or a value its rule refuses (naming the constant and the rule).
void SetConstant(PhysicsConstants* constants, const std::string& name, double value);

// "NAME=VALUE" arguments (--set, of `owval run` and `owval predict`) onto the constants, read by
// ParseAssignments (base/number_text.hpp): InputError quoting an argument that is not
// NAME=NUMBER or whose NAME was given before, and as SetConstant otherwise.
void SetConstantAssignments(PhysicsConstants* constants,
                            const std::vector<std::string>& assignments);

// Throws InputError naming the first constant whose value its rule refuses.
void ValidateConstants(const PhysicsConstants& constants);

}  // namespace owval::engine
