// Scene gates (body_gates.hpp) on constructed scenes with a known defect.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "owval/compare/parity.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/testing/reference_runs.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::compare {
namespace {

// A straight worm along z (midline rings of 8 particles, radius `radius` cu, one per bin
// 51..149), over 5 frames, sinking by `sink_cu` per frame.
Trajectory Worm(float radius, float sink_cu) {
  Trajectory t;
  t.box = {0, 40, 0, 40, 0, 60};
  t.time_step_s = 2e-5;
  for (int bin = 51; bin < 150; ++bin)
    for (int k = 0; k < 8; ++k) t.type.push_back(2.1f + float(bin - 1) * 1e-4f + 2e-5f);
  for (int f = 0; f < 5; ++f) {
    std::vector<float> frame;
    for (int bin = 51; bin < 150; ++bin)
      for (int k = 0; k < 8; ++k) {
        const double angle = 2 * M_PI * k / 8;
        frame.insert(frame.end(), {10 + radius * float(std::cos(angle)),
                                   20 - sink_cu * float(f) + radius * float(std::sin(angle)),
                                   2 + 0.5f * float(bin - 51)});
      }
    t.AppendFrame(f * 1e-3, frame.data());
  }
  return t;
}

GateStatus StatusOf(const ParityReport& r, const std::string& gate) {
  const Gate* g = r.gate(gate);
  return g ? g->status : GateStatus::kNotApplicable;
}

TEST(BodyGates, WormGatesPassForTheSameWormAndNameASwollenOne) {
  const Trajectory ref = Worm(1.5f, 0);
  const ParityReport same = CompareTrajectories(ref, ref, {});
  ASSERT_NE(same.gate("worm.cross_section_diameter"), nullptr);
  EXPECT_EQ(StatusOf(same, "worm.span"), GateStatus::kPass);
  EXPECT_EQ(StatusOf(same, "worm.cross_section_diameter"), GateStatus::kPass);
  const ParityReport swollen = CompareTrajectories(ref, Worm(1.8f, 0), {});
  EXPECT_EQ(StatusOf(swollen, "worm.cross_section_diameter"), GateStatus::kFail);
  EXPECT_NEAR(swollen.gate("worm.cross_section_diameter")->value, 0.2, 1e-5);
  EXPECT_EQ(StatusOf(swollen, "worm.span"), GateStatus::kPass);
  // Every ring swollen by 0.3 cu of the reference's mid-body 3 cu.
  EXPECT_NEAR(swollen.gate("worm.ring_diameter")->value, 0.2, 1e-5);
  EXPECT_EQ(StatusOf(same, "worm.ring_diameter"), GateStatus::kPass);
  // Sinking 1 cu a frame: 4 cu by the last frame, 4/60 of the box > 0.05.
  const ParityReport sinking = CompareTrajectories(ref, Worm(1.5f, 1.0f), {});
  EXPECT_EQ(StatusOf(sinking, "worm.centre_of_mass"), GateStatus::kFail);
  EXPECT_NEAR(sinking.gate("worm.centre_of_mass")->value, 4.0 / 60, 1e-5);
}

// Sibernetic's 0.6 s worm run with its tail quarter's rings (bins 125..149) each scaled by
// `factor` about the ring's mean from frame 1 on: the ring means, so the midline, the span and
// the centroid, are unchanged.
Trajectory WormWithScaledTail(const Trajectory& run, float factor) {
  Trajectory t = run;
  for (std::size_t f = 1; f < t.frame_count(); ++f) {
    std::map<int, std::array<double, 4>> sums;  // bin -> x, y, z, count
    for (std::size_t i = 0; i < t.particle_count(); ++i) {
      const int bin = kinematics::MidlineBin(t.type[i]);
      if (bin < 125) continue;
      for (int a = 0; a < 3; ++a) sums[bin][a] += t.position(f, i)[a];
      sums[bin][3] += 1;
    }
    for (std::size_t i = 0; i < t.particle_count(); ++i) {
      const int bin = kinematics::MidlineBin(t.type[i]);
      if (bin < 125) continue;
      for (int a = 0; a < 3; ++a) {
        const double mean = sums[bin][a] / sums[bin][3];
        t.position(f, i)[a] = float(mean + factor * (t.position(f, i)[a] - mean));
      }
    }
  }
  return t;
}

// The tail quarter crushed to 5% of its thickness passed every gate (exit 0): the
// cross-section gate averages the middle half. worm.ring_diameter sees every ring.
TEST(BodyGates, RingDiameterNamesATailCrushedWhileItsMidlineIsUnchanged) {
  const std::filesystem::path run =
      std::filesystem::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";
  if (!std::filesystem::exists(run)) GTEST_SKIP() << "no " << run;
  TextReadOptions quiet;
  quiet.quiet = true;
  const Trajectory ref = ReadTrajectory(run, quiet);
  const ParityReport crushed = CompareTrajectories(ref, WormWithScaledTail(ref, 0.05f), {});
  // The crushed tail's elastic particles are held together closer than the reference's ever are,
  // and its bonds shortened.
  EXPECT_EQ(crushed.FailedGates(), "held_pair, worm.ring_diameter, elastic.bond_length");
  EXPECT_NEAR(crushed.gate("elastic.bond_length")->value, 2.147, 0.001)
      << crushed.gate("elastic.bond_length")->detail;
  EXPECT_EQ(crushed.gate("held_pair")->detail.rfind("elastic-elastic: ", 0), 0u)
      << crushed.gate("held_pair")->value << ": " << crushed.gate("held_pair")->detail;
  EXPECT_NEAR(crushed.gate("worm.ring_diameter")->value, 0.888, 0.001);
  EXPECT_EQ(StatusOf(crushed, "worm.cross_section_diameter"), GateStatus::kPass);
  const ParityReport same = CompareTrajectories(ref, ref, {});
  EXPECT_EQ(same.gate("worm.ring_diameter")->value, 0);
  EXPECT_TRUE(same.pass());
}

// An elastic sheet at y = 10 across the box, 100 liquid particles above it; `leaked` of them
// below it from frame 1 on.
Trajectory Sheet(int leaked) {
  Trajectory t;
  t.box = {0, 20, 0, 40, 0, 20};
  t.time_step_s = 2e-5;
  for (int i = 0; i < 25; ++i) t.type.push_back(2.1f);
  for (int i = 0; i < 100; ++i) t.type.push_back(1.1f);
  for (int f = 0; f < 3; ++f) {
    std::vector<float> frame;
    for (int i = 0; i < 25; ++i)
      frame.insert(frame.end(), {float(i % 5) * 4, 10, float(i / 5) * 4});
    for (int i = 0; i < 100; ++i)
      frame.insert(frame.end(),
                   {float(i % 10), (f > 0 && i < leaked) ? 5.0f : 20.0f, float(i / 10)});
    t.AppendFrame(f * 1e-3, frame.data());
  }
  return t;
}

TEST(BodyGates, MembraneGateNamesLiquidLeakingThroughTheSheet) {
  const ParityReport tight = CompareTrajectories(Sheet(0), Sheet(2), {});
  EXPECT_EQ(StatusOf(tight, "liquid.fraction_above_membrane"), GateStatus::kPass);
  const ParityReport leaking = CompareTrajectories(Sheet(0), Sheet(30), {});
  EXPECT_EQ(StatusOf(leaking, "liquid.fraction_above_membrane"), GateStatus::kFail);
  EXPECT_NEAR(leaking.gate("liquid.fraction_above_membrane")->value, 0.3, 1e-9);
  // A scene without a sheet or a worm gets neither kind of gate.
  EXPECT_EQ(
      CompareTrajectories(Worm(1.5f, 0), Worm(1.5f, 0), {}).gate("liquid.fraction_above_membrane"),
      nullptr);
}

// `t` with `particles` moved by `offset` (cu) in x from frame 1 on.
Trajectory Moved(const Trajectory& t, const std::vector<std::size_t>& particles, float offset) {
  Trajectory out = t;
  for (std::size_t f = 1; f < out.frame_count(); ++f)
    for (std::size_t p : particles) out.position(f, p)[0] += offset;
  return out;
}

// `t` with its elastic body turned by `radians` about the vertical through its centroid, each
// frame from frame 1 on: every bond keeps its length.
Trajectory Turned(const Trajectory& t, double radians) {
  Trajectory out = t;
  const std::vector<std::size_t> elastic = GroupIndices(t, "elastic");
  for (std::size_t f = 1; f < out.frame_count(); ++f) {
    const auto c = Centroid(out, f, elastic);
    for (std::size_t p : elastic) {
      float* x = out.position(f, p);
      const double dx = x[0] - c[0], dz = x[2] - c[2];
      x[0] = float(c[0] + dx * std::cos(radians) - dz * std::sin(radians));
      x[2] = float(c[2] + dx * std::sin(radians) + dz * std::cos(radians));
    }
  }
  return out;
}

// One elastic particle of demo1's cube written 2 spacings aside (4% of the box) for the whole
// run passed every gate: its worst_particle is 0.04 of the box, under 0.05. Its bonds to its
// lattice neighbours are 2.1 spacings off.
TEST(BodyGates, BondLengthNamesOneElasticParticleWrittenTwoSpacingsAside) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& ref = *testing::SiberneticDemo1Run();
  const ParityReport r = CompareTrajectories(ref, Moved(ref, {100}, 0.04f * 88.844f), {});
  EXPECT_EQ(r.FailedGates(), "elastic.bond_length");
  const Gate& bond = *r.gate("elastic.bond_length");
  EXPECT_NEAR(bond.value, 2.128, 0.005);
  EXPECT_NE(bond.detail.find("worst bond: particles 99 and 100 at "), std::string::npos)
      << bond.detail;
  EXPECT_NE(bond.detail.find("; 924 bonds, spacing 1.67 cu"), std::string::npos) << bond.detail;
  // A tenth of the body (every tenth elastic particle) half a spacing aside fails too.
  std::vector<std::size_t> tenth;
  for (std::size_t p = 0; p < 218; p += 10) tenth.push_back(p);
  const ParityReport some = CompareTrajectories(ref, Moved(ref, tenth, 0.01f * 88.844f), {});
  EXPECT_EQ(StatusOf(some, "elastic.bond_length"), GateStatus::kFail);
  EXPECT_NEAR(some.gate("elastic.bond_length")->value, 0.53, 0.01);
}

// A length does not change when the body turns: demo1's cube turned by 30 degrees passes the bond
// gate; the run against itself measures 0, and a scene of one elastic particle has no bond (n/a).
TEST(BodyGates, BondLengthIsBlindToTurnsAndNeedsABody) {
  OWVAL_REQUIRE_DEMO1();
  const Trajectory& ref = *testing::SiberneticDemo1Run();
  const ParityReport same = CompareTrajectories(ref, ref, {});
  EXPECT_EQ(same.gate("elastic.bond_length")->status, GateStatus::kPass);
  EXPECT_EQ(same.gate("elastic.bond_length")->value, 0.0);
  EXPECT_EQ(same.gate("elastic.bond_length")->detail,
            "every bond's length equal; 924 bonds, spacing 1.67 cu");
  const ParityReport turned = CompareTrajectories(ref, Turned(ref, M_PI / 6), {});
  EXPECT_LT(turned.gate("elastic.bond_length")->value, 1e-4) << turned.FailedGates();
  const ParityReport sprig =
      CompareTrajectories(testing::BundledOneSprigRun(), testing::BundledOneSprigRun(), {});
  EXPECT_EQ(sprig.gate("elastic.bond_length")->status, GateStatus::kNotApplicable);
  EXPECT_EQ(sprig.gate("elastic.bond_length")->detail,
            "the scene has no elastic body (under two particles)");
}

// A reference with 400 of its 1,000 elastic particles heaped within half a spacing: unbounded,
// their 79,800 pairs would all be bonds. At most 32 a particle are kept.
TEST(BodyGates, BondsAreAtMost32AParticleWhateverTheReference) {
  Trajectory t;
  t.box = {0, 40, 0, 40, 0, 40};
  t.time_step_s = 2e-5;
  std::vector<float> frame;
  for (int i = 0; i < 600; ++i)  // a lattice 1 cu apart
    frame.insert(frame.end(),
                 {5.0f + float(i % 10), 5.0f + float(i / 10 % 10), 5.0f + float(i / 100)});
  for (int i = 0; i < 400; ++i)  // a heap within half a spacing of (30, 30, 30)
    frame.insert(frame.end(), {30 + 0.05f * float(i % 7), 30 + 0.05f * float(i / 7 % 7),
                               30 + 0.05f * float(i / 49)});
  t.type.assign(1000, 2.1f);
  t.AppendFrame(0, frame.data());
  t.AppendFrame(1e-3, frame.data());
  const ParityReport r = CompareTrajectories(t, t, {});
  const Gate& bond = *r.gate("elastic.bond_length");
  EXPECT_EQ(bond.status, GateStatus::kPass);
  const std::size_t at = bond.detail.find("; ") + 2;
  const std::size_t bonds = std::stoul(bond.detail.substr(at));
  EXPECT_GT(bonds, 2000u) << bond.detail;  // the lattice's 1,500 nearest and 2,000+ diagonals
  EXPECT_LE(bonds, 16000u) << bond.detail;
}

}  // namespace
}  // namespace owval::compare
