// The XPBD substrate against hand-computed positions on two or three particles.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "kernels/kernels.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/constants.hpp"
#include "owval/engine/solver.hpp"
#include "xpbd/projections.hpp"
#include "xpbd/xpbd.hpp"

namespace owval::engine::internal {
namespace {

TEST(XpbdDistance, HardConstraintMovesBothEndsByInverseMass) {
  Vec3<double> a{0, 0, 0}, b{2, 0, 0};
  double lambda = 0;
  // C = 1, Δλ = −C/(w_a + w_b) = −0.5; a moves +0.5 toward b, b moves −0.5.
  EXPECT_DOUBLE_EQ(ProjectDistance(&a, &b, 1.0, 1.0, 1.0, 0.0, &lambda), -0.5);
  EXPECT_DOUBLE_EQ(a[0], 0.5);
  EXPECT_DOUBLE_EQ(b[0], 1.5);
  EXPECT_DOUBLE_EQ(lambda, -0.5);
  // One-sided (b fixed): a takes the whole correction.
  Vec3<double> c{0, 0, 0}, d{0, 3, 0};
  double mu = 0;
  ProjectDistance(&c, &d, 1.0, 0.0, 1.0, 0.0, &mu);
  EXPECT_DOUBLE_EQ(c[1], 2.0);
  EXPECT_DOUBLE_EQ(d[1], 3.0);
}

TEST(XpbdDistance, ComplianceSoftensAndVanishingComplianceIsTheHardConstraint) {
  // α̃ = 1: Δλ = −1/(1 + 1 + 1) = −1/3.
  Vec3<double> a{0, 0, 0}, b{2, 0, 0};
  double lambda = 0;
  ProjectDistance(&a, &b, 1.0, 1.0, 1.0, 1.0, &lambda);
  EXPECT_NEAR(a[0], 1.0 / 3, 1e-15);
  EXPECT_NEAR(b[0], 5.0 / 3, 1e-15);
  // A second pass uses the accumulated λ: Δλ = (−C − α̃λ)/(2 + α̃) with C = 1/3.
  const double second = ProjectDistance(&a, &b, 1.0, 1.0, 1.0, 1.0, &lambda);
  EXPECT_NEAR(second, (-1.0 / 3 + 1.0 / 3) / 3, 1e-15);
  for (double alpha : {1e-3, 1e-6, 1e-9}) {
    Vec3<double> p{0, 0, 0}, q{2, 0, 0};
    double l = 0;
    ProjectDistance(&p, &q, 1.0, 1.0, 1.0, alpha, &l);
    EXPECT_NEAR(q[0] - p[0], 1.0, alpha) << alpha;  // error ∝ α̃ → 0
  }
}

// One elastic particle hanging from a boundary anchor, every other term off.
SiberneticConfig AnchoredParticle(float stretch_cu) {
  SiberneticConfig c;
  c.source = "anchored";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{50, 40 + 10 + stretch_cu, 50, 2.1f}, {50, 40, 50, 3.0f}};
  c.velocity = {{0, 0, 0, 0}, {0, 1, 0, 0}};
  c.connection.assign(32, {-1, 0, 0, 0});
  c.connection[0] = {1, 10, 0, 0};
  c.particle_mem_index.assign(7, -1);
  return c;
}

PhysicsConstants Quiet() {
  PhysicsConstants k;
  k.gravity = {0, 0, 0};
  k.xpbd.viscosity = 0;
  k.xpbd.surface_tension = 0;
  k.xpbd.iterations = 1;
  return k;
}

TEST(XpbdSolver, AnchoredSpringFollowsTheImplicitEulerRecurrenceFor1000Steps) {
  // One-sided bond, w = 1, α̃ = 1/(k h²), h = dt/n: each substep is u' = (u + h·v/s)/(1 + k h²),
  // v' = (u' − u)·s/h, exactly implicit Euler for u'' = −k u; its energy ½(v² + k(s u)²) never
  // grows and falls by (1 + k h²) per substep at most.
  const PhysicsConstants k = Quiet();
  const SiberneticConfig config = AnchoredParticle(0.5f);
  const int n = SubstepsOf(config, k);
  ASSERT_EQ(n, 28);  // ⌈π·√(7.5e7 s⁻²)·2e-5 s / 0.02⌉: the damping budget's rule
  Xpbd<double> solver(config, k, 1);
  const double h = double(float(k.time_step_s)) / n, s = float(k.simulation_scale);
  const double stiffness = k.elasticity_coefficient * k.non_worm_body_spring_factor;
  double u = double(float(50.5)) - 50, v = 0, energy0 = 0.5 * stiffness * (s * u) * (s * u);
  solver.Step();  // step 0 moves nothing
  double last_energy = energy0;
  for (int step = 0; step < 1000; ++step) {
    solver.Step();
    for (int sub = 0; sub < n; ++sub) {
      const double next = (u + h * v / s) / (1 + stiffness * h * h);
      v = (next - u) * s / h;
      u = next;
    }
    ASSERT_NEAR(solver.exact_positions()[0][1] - 50, u, 1e-9) << step;
    const double energy = 0.5 * (v * v + stiffness * (s * u) * (s * u));
    ASSERT_LE(energy, last_energy * (1 + 1e-12)) << step;
    last_energy = energy;
  }
  // Implicit Euler scales the energy by exactly 1/(1 + k h²) per substep (a scaled rotation of
  // (v, √k·s·u)). Over 1,000 steps (27.6 periods) that keeps 34%: ~2% of the amplitude per
  // period, the budget; without substeps it would keep (1 + k dt²)^(−1000), 1.3e-13.
  EXPECT_NEAR(last_energy / energy0, std::pow(1 + stiffness * h * h, -1000.0 * n), 1e-6);
  EXPECT_GT(last_energy / energy0, 0.33);
  EXPECT_LT(std::pow(1 + stiffness * h * h * n * n, -1000.0), 1e-12);
}

// The float solver, as runs use it: a particle at rest with no bond of its own, beside a quiet
// anchored spring that sets 28 substeps, falls under gravity. Its substep displacement from rest,
// h²g/s = 6.8e-7 cu, is under half an ulp of y = 80 cu (3.8e-6), and a velocity taken as
// (p − x)·s/h rounded it away on every substep: the particle hung in the air (as the hanging
// chain's beads did). The velocity is now v* plus the constraints' change.
TEST(XpbdSolver, AFloatParticleAtRestFallsUnderGravityWithManySubsteps) {
  SiberneticConfig c = AnchoredParticle(0.0f);  // the spring at its rest length: quiet
  c.position.insert(c.position.begin(), {20, 80, 20, 2.1f});  // elastic rows come first
  c.velocity.insert(c.velocity.begin(), {0, 0, 0, 0});
  c.connection.insert(c.connection.begin(), 32, {-1, 0, 0, 0});
  c.connection[32] = {2, 10, 0, 0};  // the anchored particle's bond, renumbered
  c.particle_mem_index.assign(14, -1);
  PhysicsConstants k = Quiet();
  k.gravity = {0, -9.8f, 0};
  ASSERT_EQ(SubstepsOf(c, k), 28);
  Xpbd<float> solver(c, k, 1);
  const int steps = 200;
  for (int step = 0; step <= steps; ++step) solver.Step();  // step 0 moves nothing
  const double t = steps * double(float(k.time_step_s)), s = float(k.simulation_scale);
  const double drop = 0.5 * 9.8 * t * t / s;  // cu
  EXPECT_NEAR(80 - solver.positions()[0].y, drop, 0.01 * drop);
}

// Two worm-body beads hanging from a boundary anchor, 4 cu apart at their rest lengths, in the
// float solver with the derived 55 substeps: their mean positions over 40 ms are the static
// sags, (2/0.25 + 1)·g/k for the lower bead (the anchor's spring is a quarter as stiff). With
// corrections under half an ulp of the position rounded away every substep, the chain's springs
// went soft below a strain of ~1% and the lower bead sagged 2.8 times too far.
TEST(XpbdSolver, AHangingChainSagsToItsStaticEquilibriumInFloat) {
  SiberneticConfig c;
  c.source = "chain";
  c.box = {0, 40, 0, 40, 0, 40};
  c.position = {{20, 30, 20, 2.1f}, {20, 26, 20, 2.1f}, {20, 34, 20, 3.0f}};
  c.velocity = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, -1, 0, 0}};
  c.connection.assign(64, {-1, 0, 0, 0});
  c.connection[0] = {2, 4, 0, 0}, c.connection[1] = {1, 4, 0, 0};
  c.connection[32] = {0, 4, 0, 0};
  c.particle_mem_index.assign(14, -1);
  PhysicsConstants k = Quiet();
  k.gravity = {0, -9.8f, 0};
  ASSERT_EQ(SubstepsOf(c, k), 55);
  Xpbd<float> solver(c, k, 1);
  const int settle = 2000, window = 2000;  // 40 ms each, ~30 periods of the slow mode
  double upper = 0, lower = 0;
  for (int step = 0; step <= settle + window; ++step) {
    solver.Step();
    if (step > settle) upper += solver.positions()[0].y, lower += solver.positions()[1].y;
  }
  const double unit = 9.8 / k.elasticity_coefficient / double(float(k.simulation_scale));  // cu
  EXPECT_NEAR(30 - upper / window, 8 * unit, 0.02 * 8 * unit);
  EXPECT_NEAR(26 - lower / window, 9 * unit, 0.02 * 9 * unit);
}

TEST(XpbdSolver, SetSubstepsReplaceTheDerivedCount) {
  PhysicsConstants k = Quiet();
  k.xpbd.substeps = 3;
  EXPECT_EQ(SubstepsOf(AnchoredParticle(0.5f), k), 3);
  k.xpbd.substeps = 0;
  k.xpbd.damping_budget = 0.04;
  EXPECT_EQ(SubstepsOf(AnchoredParticle(0.5f), k), 14);
  SiberneticConfig liquid = AnchoredParticle(0.5f);  // no bond: the floor of 4 substeps
  liquid.connection.assign(32, {-1, 0, 0, 0});
  EXPECT_EQ(SubstepsOf(liquid, k), 4);
}

// Two liquid particles 1.5 cu apart at rest, nothing else.
SiberneticConfig LiquidPair() {
  SiberneticConfig c;
  c.source = "pair";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{50, 50, 50, 1.1f}, {51.5f, 50, 50, 1.1f}};
  c.velocity.assign(2, {0, 0, 0, 0});
  return c;
}

// One density projection per step (rest density 1000 kg/m³), no other force.
PhysicsConstants OneDensityProjection() {
  PhysicsConstants k = Quiet();
  k.xpbd.rest_density = 1000;
  k.xpbd.substeps = 1;        // one projection
  k.xpbd.density_passes = 1;  // in the split scheme's one correction per step
  return k;
}

// A 3 × 3 × 3 cube of liquid particles at Sibernetic's lattice spacing r0 = h/2, at rest.
SiberneticConfig LiquidLattice() {
  SiberneticConfig c;
  c.source = "lattice";
  c.box = {0, 40, 0, 40, 0, 40};
  const float r0 = float(PhysicsConstants{}.r0_cu);
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        c.position.push_back({20 + x * r0, 20 + y * r0, 20 + z * r0, 1.1f});
  c.velocity.assign(c.position.size(), {0, 0, 0, 0});
  return c;
}

// The rest density the constraint must hold to keep PCISPH's packing is Sibernetic's ρ0 plus the
// self term, and the initial lattice, the derived default's source, reads below it. By hand, in
// units of the self term m·W(0)/s³ = m·315/(64π (h s)³) (207.53 kg/m³): the centre of the cube
// has 6 neighbours at r0, 12 at √2 r0 and 8 at √3 r0, where Wpoly6's shape (1 − r²/h²)³ is
// (3/4)³, (1/2)³ and (1/4)³, so Sibernetic's sum (no self term) reads 6·27/64 + 12/8 + 8/64 =
// 4.15625 (862.5 kg/m³, as its own density log of demo1's initial liquid,
// ../shared/reference/demo1_density_diag: 862.54) and the constraint's sum 5.15625.
TEST(XpbdSolver, SiberneticTargetIsRho0PlusTheSelfTermAndTheLatticeReadsBelowIt) {
  const PhysicsConstants k = Quiet();
  const SiberneticConfig lattice = LiquidLattice();
  const double h = float(k.h_cu), s = float(k.simulation_scale), m = float(k.mass_kg);
  const double self = m * 315 / (64 * std::numbers::pi * h * h * h * s * s * s);
  ASSERT_NEAR(self, 207.53, 0.01);
  EXPECT_NEAR(SiberneticTargetDensityOf(k), 1000 + self, 1e-9 * self);
  Xpbd<double> solver(lattice, k, 1);
  EXPECT_NEAR(solver.sibernetic_target_density(), 1000 + self, 1e-9 * self);
  EXPECT_NE(solver.parameters().find("sibernetic_target_density = 1207.5"), std::string::npos);
  // The derived default: the constraint's sum on the initial liquid with 20 or more listed
  // neighbours, here only the centre (a face's centre lists 17).
  EXPECT_NEAR(solver.rest_density(), 5.15625 * self, 1e-5 * self);
  solver.Step();  // step 0 moves nothing; the shared density phase is Sibernetic's estimator
  EXPECT_NEAR(solver.Density()[13], 4.15625 * self, 1e-4 * self);
  EXPECT_LT(solver.Density()[13], 1000);  // so PCISPH compresses the lattice
  PhysicsConstants set = k;               // a set rest density replaces the derived one
  set.xpbd.rest_density = SiberneticTargetDensityOf(k);
  EXPECT_EQ(Xpbd<double>(lattice, set, 1).rest_density(), set.xpbd.rest_density);
}

TEST(XpbdSolver, DensityConstraintOnTwoParticlesMovesThemByTheHandComputedAmount) {
  const PhysicsConstants k = OneDensityProjection();
  Xpbd<double> solver(LiquidPair(), k, 1);
  solver.Step();
  solver.Step();
  const double h = float(k.h_cu), s = float(k.simulation_scale), r = 1.5;
  const double v0 = k.mass_kg / (1000 * s * s * s);  // rest volume, cu³
  const double w = Wpoly6Coefficient(h) * (std::pow(h * h, 3) + std::pow(h * h - r * r, 3));
  const double constraint = v0 * w - 1;
  const double g = v0 * SpikyGradientCoefficient(h) * (h - r) * (h - r);  // along x_i − x_j
  const double dlambda = -constraint / (2 * g * g);
  // Δx_0 = (Δλ_0 + Δλ_1)·g·(−1) (x_0 − x_1 points along −x).
  const double dx0 = -2 * dlambda * g;
  EXPECT_NEAR(solver.exact_positions()[0][0], 50 + dx0, 1e-9);
  EXPECT_NEAR(solver.exact_positions()[1][0], 51.5 - dx0, 1e-9);
  EXPECT_LT(constraint, 0);  // below rest density: the pair is pulled together (both directions)
  EXPECT_GT(dx0, 0);
}

// Two liquid particles 1.5 cu apart, nothing else, one density projection from rest (as above),
// with [MM13]'s s_corr at strength `k`; returns particle 0's x after it.
double PairXAfterOneProjection(double k_tensile, int exponent = 4, double dq_h = 0.2) {
  PhysicsConstants k = OneDensityProjection();
  SetConstant(&k, "xpbd_tensile_correction", k_tensile);
  SetConstant(&k, "xpbd_tensile_exponent", exponent);
  SetConstant(&k, "xpbd_tensile_distance_h", dq_h);
  Xpbd<double> solver(LiquidPair(), k, 1);
  solver.Step();
  solver.Step();
  EXPECT_NEAR(solver.exact_positions()[0][0] - 50, 51.5 - solver.exact_positions()[1][0], 1e-12)
      << "the pair moves symmetrically";
  return solver.exact_positions()[0][0];
}

TEST(XpbdSolver, TensileCorrectionPushesTwoCloseParticlesApartByTheHandComputedAmount) {
  // [MM13 eqs. 13-14]: Δp_0 gains s_corr·V0∇W(p_0 − p_1), s_corr = −k·h²·(W(r)/W(0.2 h))⁴.
  const PhysicsConstants k;
  const double h = float(k.h_cu), r = 1.5;
  const double ratio = std::pow(h * h - r * r, 3) / std::pow(h * h - 0.04 * h * h, 3);
  const double s_corr = -0.1 * h * h * std::pow(ratio, 4);
  const double s = float(k.simulation_scale), v0 = k.mass_kg / (1000 * s * s * s);
  const double g = v0 * SpikyGradientCoefficient(h) * (h - r) * (h - r);  // along x_0 − x_1
  const double push = -s_corr * g;     // V0∇W(p_0 − p_1) = −g·x̂
  EXPECT_NEAR(s_corr, -0.1219, 5e-4);  // by hand: 11.1556 · 0.1 · (8.9056/10.7094)^12
  EXPECT_LT(push, 0) << "particle 0 (at lower x) is pushed away from particle 1";
  const double off = PairXAfterOneProjection(0), on = PairXAfterOneProjection(0.1);
  EXPECT_NEAR(on - off, push, 1e-9);
  EXPECT_GT(std::abs(push), 1e-3) << "a test that can fail: the push is not rounding";
  // n and |Δq| enter as the paper's: n = 2, |Δq| = 0.3 h.
  const double ratio_03 = std::pow(h * h - r * r, 3) / std::pow(h * h - 0.09 * h * h, 3);
  EXPECT_NEAR(PairXAfterOneProjection(0.1, 2, 0.3) - off, 0.1 * h * h * ratio_03 * ratio_03 * g,
              1e-9);
}

TEST(XpbdSolver, TensileCorrectionOffLeavesTheDensityCorrectionUnchanged) {
  // k = 0 is the constraint alone (the hand-computed pair above), whatever n and |Δq| say.
  const double alone = PairXAfterOneProjection(0);
  EXPECT_EQ(PairXAfterOneProjection(0, 2, 0.3), alone);
  PhysicsConstants k;
  EXPECT_EQ(k.xpbd.tensile_correction, 0) << "off by default";
  Xpbd<double> solver(AnchoredParticle(0.5f), k, 1);
  EXPECT_NE(solver.parameters().find("tensile_correction = 0,"), std::string::npos);
  SetConstant(&k, "xpbd_tensile_correction", 0.1);
  Xpbd<double> on(AnchoredParticle(0.5f), k, 1);
  EXPECT_NE(on.parameters().find("tensile_correction = 0.1 (n = 4, dq = 0.2 h)"),
            std::string::npos);
  EXPECT_THROW(SetConstant(&k, "xpbd_tensile_distance_h", 1), InputError);
  EXPECT_THROW(SetConstant(&k, "xpbd_tensile_exponent", 0), InputError);
  EXPECT_THROW(SetConstant(&k, "xpbd_tensile_correction", -0.1), InputError);
}

TEST(XpbdMembrane, APointThatCrossedATriangleGoesBackToItsPlaneAndPushesTheCorners) {
  // The triangle a = 0, b = 3x̂, c = 3ŷ in the plane z = 0; q kept on the +z side. q = (2, 0.5,
  // −0.4): its projection's barycentric weights are β = (1/6, 2/3, 1/6), C = −0.4,
  // Δλ = 0.4/(1 + 1/36 + 4/9 + 1/36) = 0.4/1.5, q moves +Δλ along z and corner k −β_k·Δλ.
  Vec3<double> q{2, 0.5, -0.4}, a{0, 0, 0}, b{3, 0, 0}, c{0, 3, 0};
  const double dlambda = 0.4 / 1.5;
  EXPECT_NEAR(ProjectPointOffTriangle(&q, &a, &b, &c, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0), dlambda,
              1e-15);
  EXPECT_NEAR(q[2], -0.4 + dlambda, 1e-15);
  EXPECT_NEAR(a[2], -dlambda / 6, 1e-15);
  EXPECT_NEAR(b[2], -2 * dlambda / 3, 1e-15);
  EXPECT_NEAR(c[2], -dlambda / 6, 1e-15);
  EXPECT_NEAR((q[2] + 0.4) + a[2] + b[2] + c[2], 0, 1e-15);  // equal masses: momentum conserved
  // q now lies on the moved corners' plane at its own (x, y): on its side, C = 0.
  EXPECT_NEAR(q[2], a[2] / 6 + 2 * b[2] / 3 + c[2] / 6, 1e-15);
  EXPECT_EQ(q[0], 2);  // the correction is along the normal only
  EXPECT_EQ(q[1], 0.5);
  // No torque: Σ r × Δr over the four (equal masses) is zero, since the corners' moves act at
  // Σ β_k·corner_k = (2, 0.5, 0), on q's line. About z nothing; about x and y:
  // q: (0.5·Δλ, −2·Δλ); a at 0: none; b: (0, +3·(2/3)Δλ) ; c: (−3·(1/6)Δλ, 0).
  const Vec3<double> start[4] = {{2, 0.5, -0.4}, {0, 0, 0}, {3, 0, 0}, {0, 3, 0}};
  const Vec3<double>* moved[4] = {&q, &a, &b, &c};
  Vec3<double> torque{0, 0, 0};
  for (int k = 0; k < 4; ++k) {
    const Vec3<double>& r = start[k];
    const Vec3<double> d{(*moved[k])[0] - r[0], (*moved[k])[1] - r[1], (*moved[k])[2] - r[2]};
    torque[0] += r[1] * d[2] - r[2] * d[1];
    torque[1] += r[2] * d[0] - r[0] * d[2];
    torque[2] += r[0] * d[1] - r[1] * d[0];
  }
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(torque[axis], 0, 1e-15) << axis;
  // A point whose projection falls outside the triangle, (3, 3) here, is no contact: pushed
  // along the normal with the reaction on the nearest edge it would make a couple.
  Vec3<double> out{3, 3, -0.1}, a4{0, 0, 0}, b4{3, 0, 0}, c4{0, 3, 0};
  EXPECT_EQ(ProjectPointOffTriangle(&out, &a4, &b4, &c4, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0), 0.0);
  EXPECT_EQ(out[2], -0.1);
  // On the edge b–c (β_a = 0) it is one: a shared edge belongs to both its triangles.
  Vec3<double> edge{1.5, 1.5, -0.1};
  EXPECT_NEAR(ProjectPointOffTriangle(&edge, &a4, &b4, &c4, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0),
              0.1 / 1.5, 1e-15);
  EXPECT_EQ(a4[2], 0.0);
  // On its side: nothing moves. The other side kept (side −1): the same point is on it.
  Vec3<double> r{1, 1, 0.2}, a2{0, 0, 0}, b2{3, 0, 0}, c2{0, 3, 0};
  EXPECT_EQ(ProjectPointOffTriangle(&r, &a2, &b2, &c2, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0), 0.0);
  EXPECT_EQ(r[2], 0.2);
  EXPECT_EQ(b2[2], 0.0);
  // Kept below (side −1), r = (1, 1, 0.2) goes down: β = 1/3 each, Δλ = 0.2/(1 + 3/9).
  EXPECT_NEAR(ProjectPointOffTriangle(&r, &a2, &b2, &c2, 1.0, 1.0, 1.0, 1.0, -1.0, 0.0),
              0.2 / (4.0 / 3), 1e-15);
  EXPECT_NEAR(r[2], 0.2 - 0.15, 1e-15);
  EXPECT_NEAR(a2[2], 0.05, 1e-15);
  // Fixed corners (w = 0) take nothing: q goes all the way back to the plane.
  Vec3<double> s{1, 1, -0.3}, a3{0, 0, 0}, b3{3, 0, 0}, c3{0, 3, 0};
  ProjectPointOffTriangle(&s, &a3, &b3, &c3, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
  EXPECT_NEAR(s[2], 0, 1e-15);
  EXPECT_EQ(a3[2], 0.0);
}

// Σ r × Δr over particles that moved from `start` to `moved` (equal masses): the change of
// angular momentum a projection makes.
template <std::size_t N>
Vec3<double> TorqueOf(const std::array<Vec3<double>, N>& start,
                      const std::array<const Vec3<double>*, N>& moved) {
  Vec3<double> torque{0, 0, 0};
  for (std::size_t k = 0; k < N; ++k) {
    const Vec3<double>& r = start[k];
    const Vec3<double> d{(*moved[k])[0] - r[0], (*moved[k])[1] - r[1], (*moved[k])[2] - r[2]};
    torque[0] += r[1] * d[2] - r[2] * d[1];
    torque[1] += r[2] * d[0] - r[0] * d[2];
    torque[2] += r[0] * d[1] - r[1] * d[0];
  }
  return torque;
}

TEST(XpbdMembrane, APointThatCrossedAnEdgeGoesBackThroughItAlongTheLineFromItsClosestPoint) {
  // The edge a = 0, b = 4x̂; q = (1, −0.3, −0.4) crossed it (side −1): its closest point is
  // e = (1, 0, 0), t = 1/4, β = (3/4, 1/4), |q − e| = 0.5, û = (0, −0.6, −0.8). With d = 0.1:
  // C = −0.5 − 0.1, Δλ = 0.6/(1 + 9/16 + 1/16) = 0.6/1.625; q −= Δλ·û, corner k += β_k·Δλ·û.
  Vec3<double> q{1, -0.3, -0.4}, a{0, 0, 0}, b{4, 0, 0};
  const std::array<Vec3<double>, 3> start{q, a, b};
  double lambda = 0;
  const double dlambda = 0.6 / 1.625;
  EXPECT_NEAR(ProjectPointOffEdge(&q, &a, &b, 1.0, 1.0, 1.0, -1.0, 0.1, 0.0, &lambda), dlambda,
              1e-15);
  EXPECT_NEAR(lambda, dlambda, 1e-15);
  const Vec3<double> u{0, -0.6, -0.8};
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(q[axis], start[0][axis] - dlambda * u[axis], 1e-15) << axis;
    EXPECT_NEAR(a[axis], 0.75 * dlambda * u[axis], 1e-15) << axis;
    EXPECT_NEAR(b[axis], start[2][axis] + 0.25 * dlambda * u[axis], 1e-15) << axis;
    // Equal masses: the three moves sum to zero (momentum conserved).
    EXPECT_NEAR(q[axis] - start[0][axis] + a[axis] + b[axis] - start[2][axis], 0, 1e-15);
    // q now sits d on the kept side of the moved edge's point (1 − t)·a + t·b, on the same line.
    EXPECT_NEAR(q[axis] - (0.75 * a[axis] + 0.25 * b[axis]), -0.1 * u[axis], 1e-15) << axis;
  }
  // No torque: the corners' moves act at e, on q's line. By hand about the origin (a's move
  // has no arm): q × (−Δλû) = −Δλ·(0, 0.8, −0.6), b × (Δλû/4) = Δλ·(0, 0.8, −0.6).
  const Vec3<double> torque = TorqueOf<3>(start, {&q, &a, &b});
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(torque[axis], 0, 1e-15) << axis;
  // A fixed edge (w = 0) takes nothing: q goes the whole 0.6 along −û.
  Vec3<double> r{1, -0.3, -0.4}, a2{0, 0, 0}, b2{4, 0, 0};
  double mu = 0;
  ProjectPointOffEdge(&r, &a2, &b2, 1.0, 0.0, 0.0, -1.0, 0.1, 0.0, &mu);
  EXPECT_NEAR(r[1], -0.3 + 0.6 * 0.6, 1e-15);
  EXPECT_NEAR(r[2], -0.4 + 0.6 * 0.8, 1e-15);
  EXPECT_EQ(a2, (Vec3<double>{0, 0, 0}));
}

TEST(XpbdMembrane, APointThatCrossedAVertexGoesBackThroughIt) {
  // v = (2, 1, 0); q = v + (−0.3, −0.4, 0) crossed it: |q − v| = 0.5, û = (−0.6, −0.8, 0),
  // d = 0.1: Δλ = 0.6/(1 + 1) = 0.3, q −= 0.3û, v += 0.3û.
  Vec3<double> q{1.7, 0.6, 0}, v{2, 1, 0};
  const std::array<Vec3<double>, 2> start{q, v};
  double lambda = 0;
  EXPECT_NEAR(ProjectPointOffVertex(&q, &v, 1.0, 1.0, -1.0, 0.1, 0.0, &lambda), 0.3, 1e-15);
  EXPECT_NEAR(q[0], 1.7 + 0.18, 1e-15);
  EXPECT_NEAR(q[1], 0.6 + 0.24, 1e-15);
  EXPECT_NEAR(v[0], 2 - 0.18, 1e-15);
  EXPECT_NEAR(v[1], 1 - 0.24, 1e-15);
  EXPECT_EQ(q[2], 0);
  // Now d past the vertex on the kept side: q − v = 0.1·(0.6, 0.8, 0) = −d·û.
  EXPECT_NEAR(q[0] - v[0], 0.06, 1e-15);
  EXPECT_NEAR(q[1] - v[1], 0.08, 1e-15);
  // Momentum and angular momentum (about the origin, v off it) conserved.
  EXPECT_NEAR(q[0] - start[0][0] + v[0] - start[1][0], 0, 1e-15);
  EXPECT_NEAR(q[1] - start[0][1] + v[1] - start[1][1], 0, 1e-15);
  const Vec3<double> torque = TorqueOf<2>(start, {&q, &v});
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(torque[axis], 0, 1e-15) << axis;
}

TEST(XpbdMembrane, EdgeAndVertexContactsLeaveAPointOnItsSideAlone) {
  // Kept side (side +1) and farther than d: nothing moves, λ untouched.
  Vec3<double> q{1, -0.3, -0.4}, a{0, 0, 0}, b{4, 0, 0};
  double lambda = 0;
  EXPECT_EQ(ProjectPointOffEdge(&q, &a, &b, 1.0, 1.0, 1.0, 1.0, 0.1, 0.0, &lambda), 0.0);
  EXPECT_EQ(q, (Vec3<double>{1, -0.3, -0.4}));
  EXPECT_EQ(b, (Vec3<double>{4, 0, 0}));
  EXPECT_EQ(lambda, 0.0);
  Vec3<double> v{1, 0.5, 0};
  EXPECT_EQ(ProjectPointOffVertex(&q, &v, 1.0, 1.0, 1.0, 0.1, 0.0, &lambda), 0.0);
  EXPECT_EQ(v, (Vec3<double>{1, 0.5, 0}));
  // Beyond the edge's end (t = 1.25) the edge is no contact: the vertex's.
  Vec3<double> beyond{5, -0.3, -0.4};
  EXPECT_EQ(ProjectPointOffEdge(&beyond, &a, &b, 1.0, 1.0, 1.0, -1.0, 0.1, 0.0, &lambda), 0.0);
  EXPECT_EQ(beyond[0], 5);
  // On its side but within d (0.05 of the edge): pushed out to d, along the same line.
  Vec3<double> near{1, 0, 0.05};
  EXPECT_NEAR(ProjectPointOffEdge(&near, &a, &b, 1.0, 0.0, 0.0, 1.0, 0.1, 0.0, &lambda), 0.05,
              1e-15);
  EXPECT_NEAR(near[2], 0.1, 1e-15);
}

TEST(XpbdMembrane, EdgeContactComplianceSoftensAndVanishingComplianceIsTheContact) {
  // The first test's edge with α̃: Δλ = 0.6/(1.625 + α̃) from λ = 0; α̃ → 0 gives the hard
  // contact's 0.6/1.625 and q at d past the edge.
  const auto dlambda_with = [](double alpha_tilde, Vec3<double>* q_out) {
    Vec3<double> q{1, -0.3, -0.4}, a{0, 0, 0}, b{4, 0, 0};
    double lambda = 0;
    const double dlambda =
        ProjectPointOffEdge(&q, &a, &b, 1.0, 1.0, 1.0, -1.0, 0.1, alpha_tilde, &lambda);
    *q_out = q;
    return dlambda;
  };
  Vec3<double> q;
  EXPECT_NEAR(dlambda_with(1.625, &q), 0.6 / 3.25, 1e-15);  // half the hard correction
  const double hard = dlambda_with(0, &q);
  EXPECT_NEAR(hard, 0.6 / 1.625, 1e-15);
  double previous_gap = 1;
  for (double alpha_tilde : {1e-2, 1e-4, 1e-6, 1e-9}) {
    Vec3<double> soft;
    const double gap = hard - dlambda_with(alpha_tilde, &soft);
    EXPECT_NEAR(gap, hard * alpha_tilde / (1.625 + alpha_tilde), 1e-15) << alpha_tilde;
    EXPECT_LT(gap, previous_gap);
    previous_gap = gap;
    EXPECT_NEAR(soft[2], q[2], alpha_tilde) << alpha_tilde;  // q's place tends to the contact's
  }
}

// Three elastic particles forming one membrane triangle in the plane z = 50 and one liquid
// particle above it, 0.5 cu off its corner a in x and y (Sibernetic's distance to a, z dropped
// and the type codes' difference kept, √(0.25 + 0.25 + 1) = 1.22 cu < r0: the triangle acts on
// it), heading down at 1.6 cu per step. No gravity, no pair forces, a density constraint too soft
// to matter.
SiberneticConfig LiquidOverATriangle() {
  SiberneticConfig c;
  c.source = "membrane";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {
      {50, 50, 50, 2.1f}, {53, 50, 50, 2.1f}, {50, 53, 50, 2.1f}, {50.5f, 50.5f, 51, 1.1f}};
  c.velocity.assign(4, {0, 0, 0, 0});
  c.connection.assign(3 * 32, {-1, 0, 0, 0});
  c.membranes = {{0, 1, 2}};
  c.particle_mem_index.assign(3 * 7, -1);
  for (int e = 0; e < 3; ++e) c.particle_mem_index[std::size_t(e) * 7] = 0;
  return c;
}

PhysicsConstants MembraneConstants(int membranes) {
  PhysicsConstants k = Quiet();
  k.xpbd.density_compliance = 1e3;  // α̃ = 2.5e12: moves nothing by more than ~1e-13 cu
  k.xpbd.membranes = membranes;
  return k;
}

TEST(XpbdSolver, MembraneConstraintKeepsTheLiquidOnItsSideAndPushesTheTriangleBack) {
  SiberneticConfig config = LiquidOverATriangle();
  const PhysicsConstants k = MembraneConstants(1);
  const double s = float(k.simulation_scale), dt = float(k.time_step_s);
  const double speed = 1.6 * s / dt;  // m/s: 1.6 cu per step
  config.velocity[3] = {0, 0, -float(speed), 0};
  Xpbd<double> solver(config, k, 1);
  EXPECT_NE(solver.parameters().find("membranes = constraint"), std::string::npos);
  solver.Step();  // step 0 moves nothing
  solver.Step();
  // Predicted to z = 51 − 1.6 = 49.4, through the plane: C = −0.6 − d (d = r0/1000, the
  // clearance) with β = (2/3, 1/6, 1/6) at (0.5, 0.5) of the 3 cu legs, Δλ = −C/(1 + 4/9 + 1/36
  // + 1/36) = (0.6 + d)/1.5.
  const double v_liquid = config.velocity[3][2];  // the float the run starts from
  const double clearance = double(float(k.r0_cu)) / 1000;
  const double predicted = 51 + v_liquid * dt / s, dlambda = (50 + clearance - predicted) / 1.5;
  const auto& x = solver.exact_positions();
  EXPECT_NEAR(dlambda, 0.4 + clearance / 1.5, 1e-6);
  EXPECT_NEAR(x[3][2], predicted + dlambda, 1e-9);
  EXPECT_NEAR(x[0][2], 50 - 2 * dlambda / 3, 1e-9);
  EXPECT_NEAR(x[1][2], 50 - dlambda / 6, 1e-9);
  EXPECT_NEAR(x[2][2], 50 - dlambda / 6, 1e-9);
  // The corners' velocities are the reaction, −β_k·Δλ·s/dt, and the momentum is the liquid's.
  const auto v = solver.velocities();
  EXPECT_NEAR(v[0].z, -2 * dlambda / 3 * s / dt, 1e-6 * speed);
  EXPECT_NEAR(v[1].z, -dlambda / 6 * s / dt, 1e-6 * speed);
  for (int step = 0; step < 20; ++step) {
    double momentum[3] = {0, 0, 0};
    for (int i = 0; i < 4; ++i) momentum[0] += v[i].x, momentum[1] += v[i].y, momentum[2] += v[i].z;
    EXPECT_NEAR(momentum[0], 0, 1e-6 * speed) << step;
    EXPECT_NEAR(momentum[1], 0, 1e-6 * speed) << step;
    EXPECT_NEAR(momentum[2], v_liquid, 1e-6 * speed) << step;
    // On its side (+z) of the corners' plane, about the clearance off it (the projection holds
    // the normal fixed while the corners, moved by different β_k, tilt it: 0.6% of d here).
    const Vec3<double> ab{x[1][0] - x[0][0], x[1][1] - x[0][1], x[1][2] - x[0][2]};
    const Vec3<double> ac{x[2][0] - x[0][0], x[2][1] - x[0][1], x[2][2] - x[0][2]};
    const Vec3<double> n{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                         ab[0] * ac[1] - ab[1] * ac[0]};
    double above = 0;
    for (int a = 0; a < 3; ++a) above += n[a] * (x[3][a] - x[0][a]) / Norm(n);
    EXPECT_GT(above, 0.9 * clearance) << step;
    solver.Step();
  }
  EXPECT_LT(x[0][2], 49);  // the triangle was carried away by the liquid
}

// Two membrane triangles folded at a right angle along the edge u = (50, 50, 50), v = (50, 50,
// 53): A = (u, v, w1) in the plane y = 50 toward w1 = (53, 50, 50), B = (u, v, w2) in x = 50
// toward w2 = (50, 53, 50). One liquid particle inside the fold, at (50.4, 50.4, 51), heading
// out through the edge at 0.8 cu per step in −x and −y (Sibernetic's distance to u and v, z
// dropped, √(0.32 + 1) = 1.15 cu < r0: both triangles act on it).
SiberneticConfig LiquidInsideAFold() {
  SiberneticConfig c;
  c.source = "fold";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{50, 50, 50, 2.1f},
                {50, 50, 53, 2.1f},
                {53, 50, 50, 2.1f},
                {50, 53, 50, 2.1f},
                {50.4f, 50.4f, 51, 1.1f}};
  c.velocity.assign(5, {0, 0, 0, 0});
  c.connection.assign(4 * 32, {-1, 0, 0, 0});
  c.membranes = {{0, 1, 2}, {0, 1, 3}};
  c.particle_mem_index.assign(4 * 7, -1);
  c.particle_mem_index[0] = 0, c.particle_mem_index[1] = 1;  // u: A, B
  c.particle_mem_index[7] = 0, c.particle_mem_index[8] = 1;  // v: A, B
  c.particle_mem_index[14] = 0;                              // w1: A
  c.particle_mem_index[21] = 1;                              // w2: B
  return c;
}

TEST(XpbdSolver, MembraneConstraintHoldsLiquidLeavingThroughAFoldsEdge) {
  SiberneticConfig config = LiquidInsideAFold();
  const PhysicsConstants k = MembraneConstants(1);
  const double s = float(k.simulation_scale), dt = float(k.time_step_s);
  const float speed = float(0.8 * s / dt);  // m/s: 0.8 cu per step
  config.velocity[4] = {-speed, -speed, 0, 0};
  Xpbd<double> solver(config, k, 1);
  solver.Step();  // step 0 moves nothing
  solver.Step();
  // Predicted to (49.6, 49.6, 51): past both planes, its projections outside both triangles, so
  // no triangle contact; the edge's: closest point e = (50, 50, 51), t = 1/3, β = (2/3, 1/3),
  // |q − e| = 0.4√2, û = −(1, 1, 0)/√2, C = −0.4√2 − d, Δλ = (0.4√2 + d)/(1 + 4/9 + 1/9);
  // q −= Δλ·û, u += (2/3)·Δλ·û, v += (1/3)·Δλ·û.
  const double step = double(speed) * dt / s;  // the float velocity's step, cu
  const double predicted = double(50.4f) - step, gap = (50 - predicted) * std::sqrt(2.0);
  const double clearance = double(float(k.r0_cu)) / 1000;
  const double dlambda = (gap + clearance) / (14.0 / 9), along = dlambda / std::sqrt(2.0);
  const auto& x = solver.exact_positions();
  EXPECT_NEAR(x[4][0], predicted + along, 1e-9);
  EXPECT_NEAR(x[4][1], predicted + along, 1e-9);
  EXPECT_NEAR(x[4][2], 51, 1e-9);
  EXPECT_NEAR(x[0][0], 50 - 2 * along / 3, 1e-9);
  EXPECT_NEAR(x[0][1], 50 - 2 * along / 3, 1e-9);
  EXPECT_NEAR(x[1][0], 50 - along / 3, 1e-9);
  EXPECT_EQ(x[2], (Vec3<double>{53, 50, 50}));  // the far corners take nothing
  EXPECT_EQ(x[3], (Vec3<double>{50, 53, 50}));
  // Inside the fold again, d past the moved edge's point (2/3)·u + (1/3)·v along −û.
  EXPECT_NEAR(x[4][0] - (2 * x[0][0] + x[1][0]) / 3, clearance / std::sqrt(2.0), 1e-9);
  // Momentum: the liquid's, now shared with the edge's corners.
  for (int frame = 0; frame < 20; ++frame) {
    const auto v = solver.velocities();
    double momentum[3] = {0, 0, 0};
    for (int i = 0; i < 5; ++i) momentum[0] += v[i].x, momentum[1] += v[i].y, momentum[2] += v[i].z;
    EXPECT_NEAR(momentum[0], -speed, 1e-6 * speed) << frame;
    EXPECT_NEAR(momentum[1], -speed, 1e-6 * speed) << frame;
    EXPECT_NEAR(momentum[2], 0, 1e-6 * speed) << frame;
    // The liquid stays inside the fold: on the +y side of A's plane or the +x side of B's.
    const auto side = [&](int a, int b, int c) {
      const Vec3<double> ab{x[b][0] - x[a][0], x[b][1] - x[a][1], x[b][2] - x[a][2]};
      const Vec3<double> ac{x[c][0] - x[a][0], x[c][1] - x[a][1], x[c][2] - x[a][2]};
      const Vec3<double> aq{x[4][0] - x[a][0], x[4][1] - x[a][1], x[4][2] - x[a][2]};
      return (ab[1] * ac[2] - ab[2] * ac[1]) * aq[0] + (ab[2] * ac[0] - ab[0] * ac[2]) * aq[1] +
             (ab[0] * ac[1] - ab[1] * ac[0]) * aq[2];
    };
    EXPECT_TRUE(side(0, 1, 2) > 0 || side(0, 1, 3) < 0) << frame;
    solver.Step();
  }
}

TEST(XpbdSolver, MembranePassMovesOnlyTheLiquid) {
  // The default (xpbd_membranes = 0): Sibernetic's pass pushes the liquid and never the body.
  SiberneticConfig config = LiquidOverATriangle();
  const PhysicsConstants k = MembraneConstants(0);
  config.velocity[3] = {0, 0, -float(1.6 * float(k.simulation_scale) / float(k.time_step_s)), 0};
  Xpbd<double> solver(config, k, 1);
  EXPECT_NE(solver.parameters().find("membranes = pass"), std::string::npos);
  for (int step = 0; step < 3; ++step) solver.Step();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(solver.velocities()[i].z, 0, 1e-6) << i;
}

// A 9 x 9 x 9 block of liquid at 0.75 r0: every interior particle has about 70 particles within
// h, so the 32-slot lists overflow and many are one-sided.
SiberneticConfig DenseLiquidBlock() {
  SiberneticConfig c;
  c.source = "dense block";
  c.box = {0, 60, 0, 60, 0, 60};
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j)
      for (int k = 0; k < 9; ++k) {
        c.position.push_back({20 + 1.25f * i, 20 + 1.25f * j, 20 + 1.25f * k, 1.1f});
        c.velocity.push_back({0, 0, 0, 1.1f});
      }
  return c;
}

// Pairs of moving particles that one lists and the other does not.
int OneSidedPairs(const ParticleState& s) {
  int one_sided = 0;
  for (std::int32_t i : s.moving)
    for (int m = 0; m < kSlots && s.slots(std::size_t(i))[m].index >= 0; ++m) {
      const std::int32_t j = s.slots(std::size_t(i))[m].index;
      const Neighbour* back = s.slots(std::size_t(j));
      bool listed = false;
      for (int n = 0; n < kSlots && back[n].index >= 0; ++n) listed |= back[n].index == i;
      one_sided += !listed;
    }
  return one_sided;
}

// An elastic particle (0) and a liquid one (1) 1.5 cu apart, nothing else, one density projection
// from rest; returns particle 0's x after it, and 1's in `x1`.
double LiquidBodyPairX(int body_push_only, double* x1) {
  PhysicsConstants k = OneDensityProjection();
  SetConstant(&k, "xpbd_body_push_only", body_push_only);
  SiberneticConfig pair = LiquidPair();
  pair.position[0][3] = 2.1f;  // elastic rows come first, with 32 connection rows each
  pair.connection.assign(32, {-1, 0, 0, 0});
  pair.particle_mem_index.assign(7, -1);
  Xpbd<double> solver(pair, k, 1);
  solver.Step();
  solver.Step();
  *x1 = solver.exact_positions()[1][0];
  return solver.exact_positions()[0][0];
}

TEST(XpbdSolver, BodyPushOnlyDropsAnUnderDenseElasticParticlesPullOnTheLiquid) {
  // Both constraints are the hand-computed pair's (C < 0, Δλ_0 = Δλ_1 = Δλ > 0). Both
  // directions: each particle moves (Δλ_0 + Δλ_1)·g toward the other. Push-only body: the
  // elastic particle's Δλ_0 > 0 counts in neither sum, so each moves Δλ_1·g, half as far, and
  // the pair stays equal and opposite.
  const PhysicsConstants k = OneDensityProjection();
  const double h = float(k.h_cu), s = float(k.simulation_scale), r = 1.5;
  const double v0 = k.mass_kg / (1000 * s * s * s);
  const double w = Wpoly6Coefficient(h) * (std::pow(h * h, 3) + std::pow(h * h - r * r, 3));
  const double g = v0 * SpikyGradientCoefficient(h) * (h - r) * (h - r);
  const double dlambda = -(v0 * w - 1) / (2 * g * g);
  ASSERT_GT(dlambda, 0) << "the pair must be under-dense for the test to mean anything";
  double x1_off = 0, x1_on = 0;
  const double x0_off = LiquidBodyPairX(0, &x1_off), x0_on = LiquidBodyPairX(1, &x1_on);
  EXPECT_NEAR(x0_off, 50 - 2 * dlambda * g, 1e-9);
  EXPECT_NEAR(x0_on, 50 - dlambda * g, 1e-9);
  EXPECT_NEAR(x1_on, 51.5 + dlambda * g, 1e-9);
  EXPECT_GT(x0_on - 50, 1e-3) << "a test that can fail: the pull is not rounding";
  PhysicsConstants defaults;
  EXPECT_EQ(defaults.xpbd.body_push_only, 0) << "off by default";
  Xpbd<double> off(AnchoredParticle(0.5f), defaults, 1);
  EXPECT_EQ(off.parameters().find("body_push_only"), std::string::npos) << "string unchanged";
  SetConstant(&defaults, "xpbd_body_push_only", 1);
  Xpbd<double> on(AnchoredParticle(0.5f), defaults, 1);
  EXPECT_NE(on.parameters().find("body_push_only = 1"), std::string::npos);
  EXPECT_THROW(SetConstant(&defaults, "xpbd_body_push_only", 2), InputError);
}

TEST(XpbdSolver, ReciprocalListsLeaveNoOneSidedPair) {
  PhysicsConstants k;
  Xpbd<float> sibernetic_lists(DenseLiquidBlock(), k, 1);
  sibernetic_lists.Step();
  EXPECT_GT(OneSidedPairs(sibernetic_lists.state()), 500) << "the block must overflow the cap";
  SetConstant(&k, "xpbd_reciprocal_lists", 1);
  Xpbd<float> reciprocal(DenseLiquidBlock(), k, 1);
  EXPECT_NE(reciprocal.parameters().find("reciprocal_lists = 1"), std::string::npos);
  EXPECT_EQ(OneSidedPairs(reciprocal.state()), 0) << "lists of the constructor's search";
  for (int step = 0; step < 3; ++step) {
    reciprocal.Step();
    EXPECT_EQ(OneSidedPairs(reciprocal.state()), 0) << "after step " << step;
  }
}

TEST(XpbdSolver, BackendByNameRecordsItsParameters) {
  RunOptions o;
  o.backend = "xpbd";
  o.duration_s = 5 * 2e-5;
  SetConstant(&o.constants, "xpbd_iterations", 2);
  RunSummary summary;
  const Trajectory t = engine::Run(AnchoredParticle(0.5f), o, &summary);
  EXPECT_FALSE(summary.reference_equivalent);
  EXPECT_EQ(t.provenance.at("producer"), "owval engine xpbd");
  EXPECT_NE(t.provenance.at("scheme_parameters").find("iterations = 2"), std::string::npos);
  EXPECT_NE(t.provenance.at("scheme_parameters").find("substeps = 28 (derived)"),
            std::string::npos);
  EXPECT_NE(t.provenance.at("scheme_parameters").find("membranes = pass"), std::string::npos);
  EXPECT_THROW(SetConstant(&o.constants, "xpbd_viscosity", 2), InputError);
  EXPECT_THROW(SetConstant(&o.constants, "xpbd_membranes", 2), InputError);  // a switch
  SetConstant(&o.constants, "xpbd_membranes", 1);
  SetConstant(&o.constants, "xpbd_density_passes", 0);  // unsplit: no contact velocity pass
  EXPECT_THROW(MakeSolver(AnchoredParticle(0.5f), o), InputError);
  SetConstant(&o.constants, "xpbd_membranes", 0);
  o.integrator = Integrator::kLeapfrog;  // PCISPH's integrator: refused, not ignored
  EXPECT_THROW(MakeSolver(AnchoredParticle(0.5f), o), InputError);
}

}  // namespace
}  // namespace owval::engine::internal
