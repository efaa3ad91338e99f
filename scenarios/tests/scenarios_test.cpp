#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "owval/base/errors.hpp"
#include "owval/compare/parity.hpp"
#include "owval/engine/config.hpp"
#include "owval/scenarios/generators.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/testing/reference_runs.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::scenarios {
namespace {
namespace fs = std::filesystem;

const fs::path kSource = OWVAL_SOURCE_DIR;

// Writes through Sibernetic's format and reads back: what the engine and Sibernetic would load.
engine::SiberneticConfig RoundTrip(const engine::SiberneticConfig& c, const std::string& name) {
  const fs::path path = owval::testing::TestScratch() / (name + ".config");
  engine::WriteSiberneticConfig(c, path);
  engine::SiberneticConfig back = engine::ReadSiberneticConfig(path);
  fs::remove(path);
  return back;
}

void ExpectRowsNear(const std::vector<engine::Row4>& a, const std::vector<engine::Row4>& b,
                    float tolerance, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  int mismatches = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 4; ++c)
      if (std::abs(a[i][c] - b[i][c]) > tolerance && ++mismatches <= 5)
        ADD_FAILURE() << what << " row " << i << " column " << c << ": " << a[i][c] << " vs "
                      << b[i][c];
  EXPECT_EQ(mismatches, 0) << what;
}

TEST(OneSprig, DefaultReproducesTheReferenceConfiguration) {
  const fs::path reference = testing::kSharedDir / "reference/one_sprig/configuration";
  if (!fs::exists(reference)) GTEST_SKIP() << "no " << reference;
  const engine::SiberneticConfig want = engine::ReadSiberneticConfig(reference);
  const engine::SiberneticConfig got = RoundTrip(OneSprig({}), "one_sprig");
  EXPECT_EQ(got.box.xmax, want.box.xmax);
  EXPECT_EQ(got.box.ymax, want.box.ymax);
  EXPECT_EQ(got.box.zmax, want.box.zmax);
  // The reference prints 6 significant digits (e.g. 0.707107, 30.895).
  ExpectRowsNear(got.position, want.position, 2e-5f, "position");
  ExpectRowsNear(got.velocity, want.velocity, 2e-6f, "velocity");
  ASSERT_EQ(got.connection.size(), want.connection.size());
  for (std::size_t r = 0; r < got.connection.size(); ++r) {
    EXPECT_EQ(std::trunc(got.connection[r][0]), std::trunc(want.connection[r][0])) << r;
    EXPECT_NEAR(got.connection[r][1], want.connection[r][1], 1e-5f) << r;
  }
  EXPECT_EQ(got.particle_mem_index, want.particle_mem_index);
  EXPECT_TRUE(got.membranes.empty());
}

TEST(OneSprig, AnchorIsTheTopWallParticleAboveTheCentre) {
  const engine::SiberneticConfig c = OneSprig({});
  EXPECT_EQ(c.particle_count(), 2169u);
  EXPECT_EQ(c.boundary_count(), 2168u);
  EXPECT_EQ(static_cast<std::size_t>(c.connection[0][0]), 1180u);
  const engine::Row4 anchor = c.position[1180];
  EXPECT_NEAR(anchor[0], 17.535f, 1e-4f);
  EXPECT_NEAR(anchor[1], 32.565f, 1e-4f);
  EXPECT_NEAR(anchor[2], 17.535f, 1e-4f);
  EXPECT_NEAR(c.connection[0][1], 14.195f, 1e-6f);
  EXPECT_EQ(c.connection.size(), 32u);
  EXPECT_EQ(c.connection[1][0], -1.0f);
}

TEST(Walls, ProperNormalsAreUnitAndPointInward) {
  WallOptions o;
  o.sites_x = 4;
  o.sites_y = 5;
  o.sites_z = 6;
  engine::SiberneticConfig c;
  // A shell of 4x5x6 sites: 120 - 2*3*4 interior.
  EXPECT_EQ(AddBoxWalls(o, &c), 96u);
  for (std::size_t i = 0; i < c.position.size(); ++i) {
    const auto& n = c.velocity[i];
    EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0f, 1e-6f) << i;
    for (int a = 0; a < 3; ++a) {
      const float centre = c.box.lower(a) + c.box.extent(a) / 2;
      EXPECT_GE(n[a] * (centre - c.position[i][a]), 0.0f) << "row " << i << " axis " << a;
    }
  }
  EXPECT_NEAR(c.box.ymax, 5 * 1.67f, 1e-5f);
}

TEST(Walls, ReferenceEdgeNormalsDropOnlyTheXComponentOfYWallEdges) {
  WallOptions o;
  o.reference_edge_normals = true;
  engine::SiberneticConfig c;
  AddBoxWalls(o, &c);
  int quirky = 0;
  for (const auto& n : c.velocity)
    quirky += std::abs(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1) > 1e-3f;
  EXPECT_EQ(quirky, 72);  // 2 x-faces * 2 y-faces * 18 interior z
}

TEST(Generators, EveryGeneratorLoadsInTheConfigReader) {
  for (const char* g : {"one_sprig", "free_fall", "hanging_chain", "liquid_column"}) {
    const engine::SiberneticConfig c = Generate(g, {});
    const engine::SiberneticConfig back = RoundTrip(c, g);
    EXPECT_EQ(back.particle_count(), c.particle_count()) << g;
    EXPECT_EQ(back.elastic_count(), c.elastic_count()) << g;
    EXPECT_EQ(back.liquid_count(), c.liquid_count()) << g;
    for (const auto& p : back.position)
      for (int a = 0; a < 3; ++a) {
        EXPECT_GT(p[a], back.box.lower(a)) << g;
        EXPECT_LT(p[a], back.box.upper(a)) << g;
      }
  }
}

TEST(Generators, HangingChainListsEverySpringFromBothEnds) {
  const engine::SiberneticConfig c = HangingChain({{"beads", 3}});
  ASSERT_EQ(c.elastic_count(), 3u);
  auto partner = [&](int bead, int slot) {
    return static_cast<int>(c.connection[bead * engine::kConnectionSlots + slot][0]);
  };
  EXPECT_EQ(KindOf(c.position[partner(0, 0)][3]), ParticleKind::kBoundary);
  EXPECT_EQ(partner(0, 1), 1);
  EXPECT_EQ(partner(1, 0), 0);
  EXPECT_EQ(partner(1, 1), 2);
  EXPECT_EQ(partner(2, 0), 1);
  EXPECT_EQ(partner(2, 1), -1);
  EXPECT_NEAR(c.position[0][1] - c.position[2][1], 8.0f, 1e-4f);
}

TEST(Generators, LiquidColumnFillsTheFloorLayers) {
  const engine::SiberneticConfig c = LiquidColumn({{"layers", 3}});
  EXPECT_EQ(c.liquid_count(), 3u * 8 * 8);
  EXPECT_EQ(c.boundary_count(), 10u * 16 * 10 - 8u * 14 * 8);
}

TEST(Generators, RefuseUnknownParametersAndImpossibleGeometry) {
  EXPECT_THROW(OneSprig({{"stiffness", 1}}), InputError);
  EXPECT_THROW(HangingChain({{"beads", 2.5}}), InputError);
  EXPECT_THROW(HangingChain({{"beads", 40}}), InputError);  // below the floor
  EXPECT_THROW(LiquidColumn({{"layers", 15}}), InputError);
  EXPECT_THROW(Generate("tornado", {}), InputError);
}

// one_sprig start_y_cu=1000 wrote a file `owval run` refused (outside the box), and
// r0_cu=1e30 one whose box no neighbour grid covers: refused here, naming the parameter.
TEST(Generators, RefuseAParticleOutsideTheBoxAndALatticeSpacingPastTheKernel) {
  auto error = [](const char* generator, const Parameters& p) -> std::string {
    try {
      Generate(generator, p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error("one_sprig", {{"start_y_cu", 1000}}),
            "one_sprig: --param start_y_cu=1000 puts the particle outside the simulation box (y "
            "from 0 to 33.4 cu)");
  for (double y : {-1.0, 1000.0, std::nan("")})
    EXPECT_NE(error("free_fall", {{"start_y_cu", y}}).find("--param start_y_cu="),
              std::string::npos)
        << y;
  EXPECT_EQ(error("one_sprig", {{"start_y_cu", 33.4}}), "no error");
  for (const char* generator : {"one_sprig", "free_fall", "hanging_chain", "liquid_column",
                                "hydrostatic_tank", "dam_break"}) {
    EXPECT_NE(error(generator, {{"r0_cu", 1e30}})
                  .find("--param r0_cu=1e+30 is not a lattice spacing "
                        "in (0, 6.68] cu"),
              std::string::npos)
        << generator << ": " << error(generator, {{"r0_cu", 1e30}});
    EXPECT_NE(error(generator, {{"r0_cu", 0}}), "no error") << generator;
  }
  EXPECT_EQ(error("free_fall", {{"r0_cu", 6.68}, {"start_y_cu", 25}}), "no error");
}

// box_sites=100000 asked for 6e10 wall particles and ran until memory ran out: every generator
// checks its lattice against the memory budget before making a particle.
TEST(Generators, ALatticeBeyondTheMemoryBudgetIsRefusedFirst) {
  auto error = [](const char* generator, const Parameters& p) -> std::string {
    try {
      Generate(generator, p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::vector<std::pair<const char*, Parameters>> huge = {
      {"one_sprig", {{"box_sites", 100000}}},
      {"free_fall", {{"box_sites", 100000}}},
      {"hanging_chain", {{"box_sites", 100000}}},
      {"liquid_column", {{"sites_xz", 100000}, {"sites_y", 100000}}},
      {"hydrostatic_tank", {{"sites_x", 100000}, {"sites_z", 100000}}},
      {"dam_break", {{"tank_sites", 100000}, {"sites_z", 100000}}}};
  for (const auto& [generator, p] : huge) {
    const std::string e = error(generator, p);
    EXPECT_EQ(e.rfind(std::string(generator) + ": a lattice of ", 0), 0u) << e;
    EXPECT_NE(e.find("more than the memory budget"), std::string::npos) << e;
  }
  EXPECT_EQ(error("hydrostatic_tank", {}), "no error");
}

// rest_length_cu=inf (or 1e300, infinite as a float) was written into the configuration as the
// spring's rest length, and reference_edge_normals=0.5, -1 or NaN read as "on".
TEST(Generators, RefuseALengthThatIsNotAFiniteFloatAndASwitchThatIsNot0Or1) {
  auto error = [](const char* generator, const Parameters& p) -> std::string {
    try {
      Generate(generator, p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  for (double length : {HUGE_VAL, 1e300, 0.0, std::nan("")})
    EXPECT_EQ(error("one_sprig", {{"rest_length_cu", length}}),
              "one_sprig: parameter 'rest_length_cu' must be a finite number > 0 (as a float, "
              "below 3.4e38)")
        << length;
  EXPECT_EQ(error("hanging_chain", {{"beads", 1}, {"spacing_cu", HUGE_VAL}}),
            "hanging_chain: parameter 'spacing_cu' must be a finite number > 0 (as a float, "
            "below 3.4e38)");
  for (const char* generator : {"one_sprig", "free_fall", "hanging_chain", "liquid_column"}) {
    for (double flag : {0.5, -1.0, 2.0, std::nan("")})
      EXPECT_EQ(error(generator, {{"reference_edge_normals", flag}}),
                std::string(generator) + ": parameter 'reference_edge_normals' must be 0 or 1")
          << generator << " " << flag;
    EXPECT_EQ(error(generator, {{"reference_edge_normals", 1}}), "no error") << generator;
    EXPECT_EQ(error(generator, {{"reference_edge_normals", 0}}), "no error") << generator;
  }
}

TEST(WcsphTanks, DamBreakColumnIsTwiceAsHighAsWideAndWallsAreThreeLayers) {
  const engine::SiberneticConfig c = DamBreak({});
  EXPECT_EQ(c.liquid_count(), 16u * 32u * 6u);
  float low_x = 1e9f, high_x = -1e9f, low_y = 1e9f, high_y = -1e9f;
  for (const auto& p : c.position) {
    if (KindOf(p[3]) != ParticleKind::kLiquid) continue;
    low_x = std::min(low_x, p[0]);
    high_x = std::max(high_x, p[0]);
    low_y = std::min(low_y, p[1]);
    high_y = std::max(high_y, p[1]);
  }
  EXPECT_NEAR((high_y - low_y + 1.67f) / (high_x - low_x + 1.67f), 2.0f, 1e-4f);
  EXPECT_NEAR(low_x, 1.67f * 3.5f, 1e-4f);  // against the third wall layer
  const engine::SiberneticConfig tank = HydrostaticTank({{"sites_x", 4}, {"sites_z", 3}});
  EXPECT_EQ(tank.liquid_count(), 4u * 24u * 3u);
  EXPECT_THROW(DamBreak({{"height_ratio", -1}}), InputError);
}

TEST(Manifests, EveryBuiltInScenarioLoadsAndGenerates) {
  const std::vector<std::string> names = ListScenarios(kSource);
  EXPECT_GE(names.size(), 4u);
  for (const std::string& name : names) {
    const Scenario s = LoadScenario(name, kSource);
    EXPECT_EQ(s.name, name);
    EXPECT_FALSE(s.predictor.empty()) << name;
    const engine::SiberneticConfig c = GenerateConfig(s);
    EXPECT_GT(c.particle_count(), 0u) << name;
    if (!s.reference.empty()) {
      EXPECT_TRUE(fs::exists(s.reference)) << name;
    }
  }
  EXPECT_THROW(LoadScenario("no_such_scenario", kSource), InputError);
}

// A name that is a path reached files beside or outside the manifests: "../manifests/one_sprig"
// loaded one_sprig, "../../x" read x.json as a manifest. Each is no scenario now.
TEST(Manifests, ANameThatIsAPathIsNoScenario) {
  for (const std::string name : {"../manifests/one_sprig", "./one_sprig", "one_sprig/",
                                 "../../scenarios/manifests/one_sprig", ".hidden"}) {
    try {
      LoadScenario(name, kSource);
      ADD_FAILURE() << name << " loaded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("no such scenario"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(LoadScenario("one_sprig", kSource).name, "one_sprig");
}

TEST(Manifests, EveryGateKeySetsItsOwnThresholdAndNoOther) {
  const auto& fields = compare::kGateThresholdFields;
  for (const compare::GateThresholdField& field : fields) {
    compare::ParityGates gates;
    ApplyManifestGates({{field.manifest_key, 0.123}}, "m.json", &gates);
    for (const compare::GateThresholdField& other : fields) {
      const compare::Threshold& t = gates.*other.member;
      const bool own = other.member == field.member;
      EXPECT_EQ(t.value == 0.123, own) << field.manifest_key << " vs " << other.manifest_key;
      EXPECT_EQ(t.source == compare::ThresholdSource::kManifest, own) << other.manifest_key;
    }
  }
  // One row per ParityGates member: ParityGates holds nothing but Thresholds.
  EXPECT_EQ(fields.size(), sizeof(compare::ParityGates) / sizeof(compare::Threshold));
  compare::ParityGates gates;
  EXPECT_THROW(ApplyManifestGates({{"frames_threshold", 0.1}}, "m.json", &gates), InputError);
}

TEST(Manifests, ResolveTakesANameOrAConfigurationFile) {
  const engine::SiberneticConfig by_name = ResolveConfig("one_sprig", kSource);
  const fs::path path = owval::testing::TestScratch() / "resolve.config";
  engine::WriteSiberneticConfig(by_name, path);
  EXPECT_EQ(ResolveConfig(path.string(), kSource).particle_count(), by_name.particle_count());
  fs::remove(path);
  EXPECT_THROW(ResolveConfig("nonexistent/config", kSource), InputError);
}

// one_sprig's manifest tightens the acceleration gate to 0.02 (docs/checklist.md, round 7): its
// bundled run with noise of 0.01 cu on each coordinate of particle 0 in every frame from frame 1
// on passed every gate of the manifest (half_amplitude 0.475% of its 0.5%), and the checklist
// said ready; the default 0.25, set by demo1's chaotic reruns (up to 0.12), admits it (0.24).
// An honest port of this oscillator measures far less: owval's leapfrog 0.0037.
TEST(Manifests, OneSprigsAccelerationGateFailsANoisyCopyOfItsReference) {
  const Scenario one_sprig = LoadScenario("one_sprig", kSource);
  EXPECT_EQ(one_sprig.gates.acceleration.value, 0.02);
  const Trajectory& run = owval::testing::BundledOneSprigRun();
  Trajectory noisy = run;
  std::mt19937 random(1);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  for (std::size_t f = 1; f < noisy.frame_count(); ++f)
    for (int a = 0; a < 3; ++a)
      noisy.position(f, 0)[a] = float(noisy.position(f, 0)[a] + noise(random));
  compare::ParityOptions options;
  options.track = one_sprig.track;
  options.gates = one_sprig.gates;
  const compare::ParityReport judged = compare::CompareTrajectories(run, noisy, options);
  EXPECT_EQ(judged.FailedGates(), "acceleration");
  EXPECT_NEAR(judged.gate("acceleration")->value, 0.24, 0.02);
  EXPECT_TRUE(compare::CompareTrajectories(run, run, options).pass());
  options.gates.acceleration = compare::ParityGates{}.acceleration;
  EXPECT_TRUE(compare::CompareTrajectories(run, noisy, options).pass());
}

}  // namespace
}  // namespace owval::scenarios
