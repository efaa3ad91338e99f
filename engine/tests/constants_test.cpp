// The one table of physics constants: every field settable by name, non-physical values refused.
#include "owval/engine/constants.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/engine/run.hpp"

namespace owval::engine {
namespace {

std::string ErrorOf(const PhysicsConstants& start, const std::string& name, double value) {
  PhysicsConstants c = start;
  try {
    SetConstant(&c, name, value);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Constants, EveryEntrySetsItsOwnFieldAndOnlyIt) {
  std::set<std::string> names;
  for (const ConstantInfo& info : PhysicsConstantTable()) {
    EXPECT_TRUE(names.insert(info.name).second) << "duplicate " << info.name;
    PhysicsConstants c;
    // A valid value other than the default, for each rule.
    const double value = info.rule == ConstantRule::kSwitch         ? 1 - info.get(c)
                         : info.rule == ConstantRule::kFraction     ? 0.5
                         : info.rule == ConstantRule::kOpenFraction ? 0.5
                                                                    : info.get(c) + 2;
    SetConstant(&c, info.name, value);
    EXPECT_EQ(info.get(c), value) << info.name;
    // Exactly this constant differs from the defaults now; scheme parameters are not listed.
    const std::string differences = c.DifferencesFromDefaults();
    if (info.scheme) {
      EXPECT_EQ(differences, "") << info.name;
      continue;
    }
    EXPECT_EQ(differences.rfind(std::string(info.name) + " = ", 0), 0u) << differences;
    EXPECT_EQ(differences.find(','), std::string::npos) << differences;
    EXPECT_NE(info.unit, nullptr);
    EXPECT_GT(std::string(info.doc).size(), 5u);
  }
  // h, r0 and the iteration count are settable like the rest.
  for (const char* name : {"h_cu", "r0_cu", "pcisph_iterations", "delta", "viscosity"})
    EXPECT_TRUE(names.count(name)) << name;
  EXPECT_TRUE(PhysicsConstants{}.DifferencesFromDefaults().empty());
}

TEST(Constants, NonPhysicalValuesAreInputErrorsNamingTheConstant) {
  const double inf = std::numeric_limits<double>::infinity();
  const PhysicsConstants d;
  const std::pair<const char*, double> refused[] = {{"time_step_s", 0},
                                                    {"time_step_s", -1},
                                                    {"time_step_s", NAN},
                                                    {"mass_kg", -1},
                                                    {"mass_kg", 0},
                                                    {"mass_kg", 1e-50},
                                                    {"rest_density", 0},
                                                    {"h_cu", 0},
                                                    {"r0_cu", -1.67},
                                                    {"simulation_scale", 1e39},
                                                    {"delta", inf},
                                                    {"delta", -0.1},
                                                    {"pcisph_iterations", 0},
                                                    {"pcisph_iterations", 2.5},
                                                    {"gravity_y", NAN},
                                                    {"elasticity_coefficient", -1},
                                                    {"xpbd_substeps", -1},
                                                    {"xpbd_substeps", 1.5},
                                                    {"xpbd_damping_budget", 0},
                                                    {"xpbd_damping_budget", 1}};
  for (const auto& [name, value] : refused) {
    const std::string what = ErrorOf(d, name, value);
    EXPECT_NE(what.find(name), std::string::npos) << name << " = " << value << ": " << what;
    EXPECT_NE(what.find("not physical"), std::string::npos) << what;
  }
  const std::string unknown = ErrorOf(d, "stiffness", 1);
  EXPECT_NE(unknown.find("unknown engine constant 'stiffness'"), std::string::npos) << unknown;
  // The nearest names and where every one is listed: the whole list ran past a line.
  EXPECT_NE(unknown.find("(nearest: "), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("owval run --help lists all"), std::string::npos) << unknown;
  EXPECT_LT(unknown.size(), 160u) << unknown;
  EXPECT_NE(ErrorOf(d, "pcisph_iteration", 5).find("(nearest: pcisph_iterations, "),
            std::string::npos);
  EXPECT_EQ(ErrorOf(d, "gravity_y", -20), "");
  EXPECT_EQ(ErrorOf(d, "pcisph_iterations", 5), "");
}

SiberneticConfig TwoLiquidParticles() {
  SiberneticConfig c;
  c.source = "two";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{50, 50, 50, 1.1f}, {50.5f, 50, 50, 1.1f}};  // within hS/4: repulsion
  c.velocity.assign(2, {0, 0, 0, 0});
  return c;
}

TEST(Constants, RunRefusesNonPhysicalConstantsAndStepCounts) {
  RunOptions o;
  o.duration_s = 10 * 2e-5;
  o.constants.rest_density = 0;
  EXPECT_THROW(engine::Run(TwoLiquidParticles(), o), InputError);
  o.constants = {};
  o.constants.pcisph_iterations = 0;
  EXPECT_THROW(engine::Run(TwoLiquidParticles(), o), InputError);
  o.constants = {};
  for (double duration_s : {0.0, -1.0, double(NAN), 1e15}) {
    o.duration_s = duration_s;
    EXPECT_THROW(engine::Run(TwoLiquidParticles(), o), InputError) << duration_s;
  }
}

// A compressed 4x4x4 block of liquid (spacing 1.4 cu < r0): densities above rho0, so the
// pressure loop has work to do.
SiberneticConfig CompressedBlock() {
  SiberneticConfig c;
  c.source = "block";
  c.box = {0, 100, 0, 100, 0, 100};
  for (int i = 0; i < 64; ++i)
    c.position.push_back(
        {50 + 1.4f * float(i % 4), 50 + 1.4f * float(i / 4 % 4), 50 + 1.4f * float(i / 16), 1.1f});
  c.velocity.assign(64, {0, 0, 0, 0});
  return c;
}

TEST(Constants, IterationCountAndSmoothingRadiusChangeARun) {
  RunOptions o;
  o.duration_s = 20 * 2e-5;
  const Trajectory base = engine::Run(CompressedBlock(), o);
  for (const auto& [name, value] : {std::pair{"pcisph_iterations", 1.0}, {"h_cu", 3.0}}) {
    RunOptions changed = o;
    SetConstant(&changed.constants, name, value);
    RunSummary summary;
    const Trajectory t = engine::Run(CompressedBlock(), changed, &summary);
    EXPECT_FALSE(summary.reference_equivalent) << name;
    EXPECT_NE(t.coordinate(19, 1, 0), base.coordinate(19, 1, 0)) << name;
    EXPECT_NE(t.provenance.at("constants").find(name), std::string::npos) << name;
  }
}

TEST(Constants, PhysicalParametersUseTheTablesSiberneticNames) {
  SiberneticConfig c = TwoLiquidParticles();
  c.physical_parameters = {{"maxIteration", 5}, {"rho0", 998}, {"surfTensCoeff", 1}};
  PhysicsConstants k;
  std::vector<std::string> ignored;
  EXPECT_EQ(ApplyPhysicalParameters(c, &k, &ignored).size(), 2u);
  EXPECT_EQ(k.pcisph_iterations, 5);
  EXPECT_EQ(k.rest_density, 998);
  EXPECT_EQ(ignored, std::vector<std::string>{"surfTensCoeff"});
  c.physical_parameters = {{"rho0", 0}};
  EXPECT_THROW(ApplyPhysicalParameters(c, &k), InputError);
}

}  // namespace
}  // namespace owval::engine
