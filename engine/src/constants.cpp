// The physics constants' table and everything that names a constant: --set, [physical
// parameters], validation and the provenance's list of differences.
#include "owval/engine/constants.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <vector>

#include "owval/base/errors.hpp"
#include "owval/base/number_text.hpp"
#include "owval/base/one_line.hpp"

namespace owval::engine {
namespace {

// Getter and setter of one PhysicsConstants field, as the table's function pointers.
#define OWVAL_FIELD(field)                                                                       \
  [](const PhysicsConstants& c) { return double(c.field); }, [](PhysicsConstants& c, double v) { \
    c.field = static_cast<std::remove_cvref_t<decltype(c.field)>>(v);                            \
  }
#define OWVAL_COMPONENT(array, a)                       \
  [](const PhysicsConstants& c) { return c.array[a]; }, \
      [](PhysicsConstants& c, double v) { c.array[a] = v; }

using R = ConstantRule;

// Sibernetic's names from owConfigProperty.cpp:160-224 (physics sheet §1).
const ConstantInfo kTable[] = {
    {"mass_kg", "mass", "kg", "particle mass m (owPhysicsConstant.h:54)", R::kPositive, nullptr,
     OWVAL_FIELD(mass_kg)},
    {"rest_density", "rho0", "kg/m^3", "rest density rho0 of PCISPH's pressure correction",
     R::kPositive, nullptr, OWVAL_FIELD(rest_density)},
    {"time_step_s", "timeStep", "s", "time step dt (delta is not recomputed from it)", R::kPositive,
     nullptr, OWVAL_FIELD(time_step_s)},
    {"simulation_scale", "simulationScale", "m/cu", "metres per configuration unit s", R::kPositive,
     nullptr, OWVAL_FIELD(simulation_scale)},
    {"h_cu", "h", "cu", "smoothing radius h (hash cells are 2h wide)", R::kPositive, nullptr,
     OWVAL_FIELD(h_cu)},
    {"r0_cu", "r0", "cu", "wall and membrane interaction radius r0 (Sibernetic: h/2)", R::kPositive,
     nullptr, OWVAL_FIELD(r0_cu)},
    {"elasticity_coefficient", "elasticityCoefficient", "1/s^2",
     "spring stiffness k per unit mass between worm-body particles", R::kNonNegative, nullptr,
     OWVAL_FIELD(elasticity_coefficient)},
    {"max_muscle_force", "max_muscle_force", "m/s^2",
     "muscle pull per unit activation (Sibernetic applies it as an acceleration)", R::kNonNegative,
     nullptr, OWVAL_FIELD(max_muscle_force)},
    {"gravity_x", "gravity_x", "m/s^2", "gravity, x component", R::kFinite, nullptr,
     OWVAL_COMPONENT(gravity, 0)},
    {"gravity_y", "gravity_y", "m/s^2", "gravity, y component", R::kFinite, nullptr,
     OWVAL_COMPONENT(gravity, 1)},
    {"gravity_z", "gravity_z", "m/s^2", "gravity, z component", R::kFinite, nullptr,
     OWVAL_COMPONENT(gravity, 2)},
    {"pcisph_iterations", "maxIteration", "1", "PCISPH prediction-correction passes per step",
     R::kIntegerAtLeastOne, nullptr, OWVAL_FIELD(pcisph_iterations)},
    {"delta", nullptr, "Pa/(kg/m^3)",
     "PCISPH pressure scaling delta (Sibernetic fixes it from the default dt)", R::kNonNegative,
     nullptr, OWVAL_FIELD(delta)},
    {"surface_tension_scale", nullptr, "1",
     "factor of surfTensCoeff in the cohesion term (sphFluid.cl:645-655)", R::kNonNegative, nullptr,
     OWVAL_FIELD(surface_tension_scale)},
    {"viscosity", "viscosity", "Pa s", "viscosity (never used by Sibernetic's kernels)",
     R::kNonNegative, nullptr, OWVAL_FIELD(viscosity)},
    {"non_worm_body_spring_factor", nullptr, "1",
     "stiffness factor of springs not between two worm-body particles (sphFluid.cl:723-731)",
     R::kNonNegative, nullptr, OWVAL_FIELD(non_worm_body_spring_factor)},
    {"xpbd_iterations", nullptr, "1", "XPBD constraint projection passes per substep (K)",
     R::kIntegerAtLeastOne, "xpbd", OWVAL_FIELD(xpbd.iterations)},
    {"xpbd_substeps", nullptr, "1",
     "XPBD substeps of dt/n per step; 0: derived from the stiffest bond and the damping budget",
     R::kCount, "xpbd", OWVAL_FIELD(xpbd.substeps)},
    {"xpbd_density_passes", nullptr, "1",
     "XPBD density and wall corrections per step (bonds on every substep); 0: every constraint "
     "on every substep",
     R::kCount, "xpbd", OWVAL_FIELD(xpbd.density_passes)},
    {"xpbd_damping_budget", nullptr, "1",
     "XPBD: amplitude fraction the stiffest bond may lose per period (sets the derived substeps)",
     R::kOpenFraction, "xpbd", OWVAL_FIELD(xpbd.damping_budget)},
    {"xpbd_density_compliance", nullptr, "s^2/cu^2",
     "XPBD compliance of C = rho/rho_rest - 1; 0: derived, (s/c)^2 with c = 10 sqrt(2 g H)",
     R::kNonNegative, "xpbd", OWVAL_FIELD(xpbd.density_compliance)},
    {"xpbd_bond_compliance_scale", nullptr, "1",
     "XPBD bond compliance = scale / k_eff, k_eff the bond's Sibernetic stiffness", R::kNonNegative,
     "xpbd", OWVAL_FIELD(xpbd.bond_compliance_scale)},
    {"xpbd_rest_density", nullptr, "kg/m^3",
     "XPBD rest density; 0: the mean initial density of the configuration's interior liquid",
     R::kNonNegative, "xpbd", OWVAL_FIELD(xpbd.rest_density)},
    {"xpbd_floor_restitution", nullptr, "1",
     "XPBD restitution at the box's floor and wall contacts", R::kFraction, "xpbd",
     OWVAL_FIELD(xpbd.floor_restitution)},
    {"xpbd_muscle_strength", nullptr, "1", "XPBD muscle bond k(t) = k (1 + activation strength)",
     R::kNonNegative, "xpbd", OWVAL_FIELD(xpbd.muscle_strength)},
    {"xpbd_viscosity", nullptr, "1", "XPBD: 1 adds Sibernetic's viscosity force", R::kSwitch,
     "xpbd", OWVAL_FIELD(xpbd.viscosity)},
    {"xpbd_surface_tension", nullptr, "1", "XPBD: 1 adds Sibernetic's cohesion force", R::kSwitch,
     "xpbd", OWVAL_FIELD(xpbd.surface_tension)},
    {"xpbd_pressure_force", nullptr, "1", "XPBD: 1 adds the SPH pressure-gradient force",
     R::kSwitch, "xpbd", OWVAL_FIELD(xpbd.pressure_force)},
    {"xpbd_membranes", nullptr, "1",
     "XPBD: 0 Sibernetic's membrane pass once per step (liquid only); 1 a liquid-triangle "
     "contact constraint in the projection passes, shared with the triangle's corners",
     R::kSwitch, "xpbd", OWVAL_FIELD(xpbd.membranes)},
    {"xpbd_reciprocal_lists", nullptr, "1",
     "XPBD: 1 keeps a pair of moving particles in the neighbour lists only when each lists the "
     "other (equal and opposite pair terms); 0 Sibernetic's capped lists as searched",
     R::kSwitch, "xpbd", OWVAL_FIELD(xpbd.reciprocal_lists)},
    {"xpbd_body_push_only", nullptr, "1",
     "XPBD: 1 in a pair of a liquid and an elastic particle, the elastic particle's density "
     "multiplier only pushes (an under-dense body does not pull the liquid in, as PCISPH's "
     "clamped pressure); 0 both directions",
     R::kSwitch, "xpbd", OWVAL_FIELD(xpbd.body_push_only)},
    {"xpbd_tensile_correction", nullptr, "1",
     "XPBD: k of position-based fluids' artificial pressure s_corr = -k (W(r)/W(dq))^n in the "
     "density correction (Macklin & Mueller 2013 eq. 13; paper 0.1), in units of h^2; 0 off",
     R::kNonNegative, "xpbd", OWVAL_FIELD(xpbd.tensile_correction)},
    {"xpbd_tensile_exponent", nullptr, "1", "XPBD: n of s_corr (paper 4)", R::kIntegerAtLeastOne,
     "xpbd", OWVAL_FIELD(xpbd.tensile_exponent)},
    {"xpbd_tensile_distance_h", nullptr, "h",
     "XPBD: |dq| of s_corr as a fraction of h (paper 0.1-0.3)", R::kOpenFraction, "xpbd",
     OWVAL_FIELD(xpbd.tensile_distance_h)},
    {"wcsph_h_factor", nullptr, "1", "WCSPH smoothing length h / particle spacing (support 2h)",
     R::kPositive, "wcsph", OWVAL_FIELD(wcsph.h_factor)},
    {"wcsph_spacing_m", nullptr, "m",
     "WCSPH particle spacing; 0: the median nearest-neighbour distance of the liquid",
     R::kNonNegative, "wcsph", OWVAL_FIELD(wcsph.spacing_m)},
    {"wcsph_sound_speed_factor", nullptr, "1",
     "WCSPH c_s = max(factor sqrt(2 g H), c_min), H the liquid's height", R::kPositive, "wcsph",
     OWVAL_FIELD(wcsph.sound_speed_factor)},
    {"wcsph_min_sound_speed_m_s", nullptr, "m/s", "WCSPH c_min, the speed of sound's floor",
     R::kNonNegative, "wcsph", OWVAL_FIELD(wcsph.min_sound_speed_m_s)},
    {"wcsph_tait_gamma", nullptr, "1", "WCSPH Tait exponent gamma", R::kPositive, "wcsph",
     OWVAL_FIELD(wcsph.tait_gamma)},
    {"wcsph_cfl", nullptr, "1", "WCSPH CFL number of dt_safe", R::kPositive, "wcsph",
     OWVAL_FIELD(wcsph.cfl)},
    {"wcsph_density_diffusion", nullptr, "1", "WCSPH: 1 adds delta-SPH density diffusion",
     R::kSwitch, "wcsph", OWVAL_FIELD(wcsph.density_diffusion)},
    {"wcsph_diffusion_delta", nullptr, "1", "WCSPH delta-SPH coefficient delta", R::kNonNegative,
     "wcsph", OWVAL_FIELD(wcsph.diffusion_delta)},
    {"wcsph_xsph", nullptr, "1", "WCSPH: 1 moves particles with XSPH-smoothed velocities",
     R::kSwitch, "wcsph", OWVAL_FIELD(wcsph.xsph)},
    {"wcsph_xsph_epsilon", nullptr, "1", "WCSPH XSPH epsilon", R::kFraction, "wcsph",
     OWVAL_FIELD(wcsph.xsph_epsilon)},
    {"wcsph_viscosity_alpha", nullptr, "1", "WCSPH Monaghan artificial viscosity alpha",
     R::kNonNegative, "wcsph", OWVAL_FIELD(wcsph.viscosity_alpha)},
    {"wcsph_optimistic_dt", nullptr, "1",
     "WCSPH: 1 tries factor x dt_safe and rolls back past the threshold, 0 steps dt_safe",
     R::kSwitch, "wcsph", OWVAL_FIELD(wcsph.optimistic_dt)},
    {"wcsph_optimistic_factor", nullptr, "1", "WCSPH optimistic step as a multiple of dt_safe",
     R::kPositive, "wcsph", OWVAL_FIELD(wcsph.optimistic_factor)},
    {"wcsph_rollback_threshold", nullptr, "1",
     "WCSPH max |rho - rho0|/rho0 after a step that rolls it back", R::kPositive, "wcsph",
     OWVAL_FIELD(wcsph.rollback_threshold)},
    {"wcsph_cooldown_steps", nullptr, "1", "WCSPH steps at dt_safe after a rollback",
     R::kIntegerAtLeastOne, "wcsph", OWVAL_FIELD(wcsph.cooldown_steps)},
    {"wcsph_morton_reorder", nullptr, "1", "WCSPH: 1 reorders particles along a Morton curve",
     R::kSwitch, "wcsph", OWVAL_FIELD(wcsph.morton_reorder)},
    {"wcsph_reorder_interval", nullptr, "1", "WCSPH steps between Morton reorders",
     R::kIntegerAtLeastOne, "wcsph", OWVAL_FIELD(wcsph.reorder_interval)},
    {"wcsph_hydrostatic_start", nullptr, "1",
     "WCSPH: 1 starts densities on the hydrostatic Tait profile, 0 at rho0", R::kSwitch, "wcsph",
     OWVAL_FIELD(wcsph.hydrostatic_start)},
};

#undef OWVAL_FIELD
#undef OWVAL_COMPONENT

// Edits (insert, delete, replace a character) from `a` to `b`.
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The three names nearest to `name`: the whole list ran past a line (`owval run --help` has it).
std::string NearestNames(const std::string& name) {
  std::vector<std::pair<std::size_t, const char*>> by_distance;
  for (const ConstantInfo& c : kTable) by_distance.emplace_back(EditDistance(name, c.name), c.name);
  std::stable_sort(by_distance.begin(), by_distance.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string nearest;
  for (std::size_t k = 0; k < 3 && k < by_distance.size(); ++k)
    nearest += (k ? ", " : "") + std::string(by_distance[k].second);
  return nearest;
}

}  // namespace

std::span<const ConstantInfo> PhysicsConstantTable() { return kTable; }

const ConstantInfo* FindConstant(const std::string& name) {
  for (const ConstantInfo& c : kTable)
    if (name == c.name) return &c;
  return nullptr;
}

std::string CheckConstant(const ConstantInfo& constant, double value) {
  const float f = static_cast<float>(value);  // what the engine computes with
  switch (constant.rule) {
    case R::kFinite:
      return std::isfinite(f) ? "" : "a finite number (as a float)";
    case R::kPositive:
      return std::isfinite(f) && f > 0 ? "" : "a finite number > 0 (as a float)";
    case R::kNonNegative:
      return std::isfinite(f) && f >= 0 ? "" : "a finite number >= 0 (as a float)";
    case R::kIntegerAtLeastOne:
      return value >= 1 && value <= 1000 && value == std::floor(value)
                 ? ""
                 : "a whole number in 1..1000";
    case R::kSwitch:
      return value == 0 || value == 1 ? "" : "0 or 1";
    case R::kFraction:
      return value >= 0 && value <= 1 ? "" : "a number in [0, 1]";
    case R::kCount:
      return value >= 0 && value <= 1000 && value == std::floor(value)
                 ? ""
                 : "a whole number in 0..1000";
    case R::kOpenFraction:
      return value > 0 && value < 1 ? "" : "a number in (0, 1)";
  }
  return "";
}

void SetConstant(PhysicsConstants* constants, const std::string& name, double value) {
  const ConstantInfo* c = FindConstant(name);
  if (!c)
    throw InputError("unknown engine constant '" + OneLine(name, 40) +
                     "' (nearest: " + NearestNames(name) + "; owval run --help lists all " +
                     std::to_string(std::size(kTable)) + ")");
  const std::string expected = CheckConstant(*c, value);
  if (!expected.empty()) {
    std::ostringstream msg;
    msg << "engine constant " << name << " = " << value << " is not physical: expected " << expected
        << " (" << c->unit << ")";
    throw InputError(msg.str());
  }
  c->set(*constants, value);
}

void ValidateConstants(const PhysicsConstants& constants) {
  for (const ConstantInfo& c : kTable) {
    const double value = c.get(constants);
    const std::string expected = CheckConstant(c, value);
    if (expected.empty()) continue;
    std::ostringstream msg;
    msg << "engine constant " << c.name << " = " << value << " is not physical: expected "
        << expected << " (" << c.unit << ")";
    throw InputError(msg.str());
  }
}

std::string PhysicsConstants::DifferencesFromDefaults() const {
  const PhysicsConstants d;
  std::ostringstream s;
  for (const ConstantInfo& c : kTable) {
    if (c.scheme) continue;
    const double a = c.get(*this), b = c.get(d);
    if (a != b)
      s << (s.tellp() > 0 ? ", " : "") << c.name << " = " << a << " (default " << b << ")";
  }
  return s.str();
}

std::vector<std::string> ApplyPhysicalParameters(const SiberneticConfig& config,
                                                 PhysicsConstants* constants,
                                                 std::vector<std::string>* ignored) {
  std::vector<std::string> applied;
  for (const auto& [name, value] : config.physical_parameters) {
    const ConstantInfo* match = nullptr;
    for (const ConstantInfo& c : kTable)
      if (c.sibernetic_name && name == c.sibernetic_name) match = &c;
    if (!match) {
      if (ignored) ignored->push_back(name);
      continue;
    }
    const std::string expected = CheckConstant(*match, value);
    if (!expected.empty())
      throw InputError(config.source, 0,
                       "[physical parameters] " + name + " (" + match->name +
                           ") is not physical: expected " + expected);
    match->set(*constants, value);
    applied.push_back(name);
  }
  return applied;
}

void SetConstantAssignments(PhysicsConstants* constants,
                            const std::vector<std::string>& assignments) {
  for (const auto& [name, value] : ParseAssignments(assignments, "--set"))
    SetConstant(constants, name, value);
}

}  // namespace owval::engine
