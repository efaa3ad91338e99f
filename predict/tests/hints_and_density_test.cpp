// Reconciliation hints on constructed signals with a known defect, and the hydrostatic
// predictor's Sibernetic density of a starting lattice, against values computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "owval/predict/predict.hpp"

namespace owval::predict {
namespace {

using engine::SiberneticConfig;

constexpr double kScale = 7.39999905e-06;  // m per cu (Sibernetic's simulationScale)

double Value(const Prediction& p, const std::string& name) {
  if (!p.Find(name)) throw std::runtime_error("no quantity " + name);
  return p.ValueOf(name);
}
const ReconcileRow& Row(const Reconciliation& r, const std::string& name) {
  if (!r.Find(name)) throw std::runtime_error("no row " + name);
  return *r.Find(name);
}

void AddParticle(SiberneticConfig* c, float x, float y, float z, float type) {
  c->position.push_back({x, y, z, type});
  c->velocity.push_back({0, 0, 0, 0});
}

SiberneticConfig Box() {
  SiberneticConfig c;
  c.source = "constructed (test)";
  c.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  return c;
}

// Sibernetic's one_sprig reduced to its two particles: 2.1 at y = 20.04 on a 14.195 cu spring
// to a wall particle at y = 32.565.
SiberneticConfig OneSprig() {
  SiberneticConfig c = Box();
  AddParticle(&c, 17.535f, 20.04f, 17.535f, 2.1f);
  AddParticle(&c, 17.535f, 32.565f, 17.535f, 3.0f);
  c.connection.push_back({1, 14.195f, 0, 0});
  for (int slot = 1; slot < engine::kConnectionSlots; ++slot)
    c.connection.push_back({-1, -1, 0, 0});
  for (int m = 0; m < engine::kMembraneSlotsPerParticle; ++m) c.particle_mem_index.push_back(-1);
  return c;
}

// Particle 0 of type `type` with y(t) per frame, and a wall particle.
template <typename F>
Trajectory Synthetic(int frames, double dt, float type, F y) {
  Trajectory t;
  t.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  t.time_step_s = dt;
  t.type = {type, 3.0f};
  for (int f = 0; f < frames; ++f) {
    t.time_s.push_back(f * dt);
    t.positions.insert(t.positions.end(), {17.535f, float(y(f * dt)), 17.535f});
    t.positions.insert(t.positions.end(), {17.535f, 32.565f, 17.535f});
  }
  return t;
}

TEST(Hints, DampedOscillationPointsToViscousCoupling) {
  const Prediction p = Predict(OneSprig(), {}, {});
  const double omega = 2 * M_PI / Value(p, "zero_crossing_period");
  const double y_eq = Value(p, "equilibrium"), a = Value(p, "half_amplitude");
  // Amplitude e^-0.35 per period: whole-cycle half-amplitude falls far below the prediction.
  const Trajectory t = Synthetic(1000, 2e-5, 2.1f, [&](double s) {
    return y_eq + a * std::exp(-0.35 * s * omega / (2 * M_PI)) * std::cos(omega * s);
  });
  const Reconciliation r = Reconcile(p, t);
  EXPECT_FALSE(r.pass);
  EXPECT_NE(Row(r, "half_amplitude").hint.find("viscous"), std::string::npos) << r.ToJson().dump(2);
}

TEST(Hints, FreeFallFasterThanPredictedPointsToBuoyancy) {
  SiberneticConfig c = Box();
  AddParticle(&c, 16.7f, 25.0f, 16.7f, 1.1f);
  AddParticle(&c, 16.7f, 0.835f, 16.7f, 3.0f);
  const Prediction p = Predict(c, {}, {});
  auto fall = [](double g) { return [g](double s) { return 25.0 - 0.5 * g * s * s / kScale; }; };
  // Continuous fall with g: crosses 4.175 cu at 5.6080 ms, 0.18% after the discrete prediction.
  const Reconciliation ok = Reconcile(p, Synthetic(400, 2e-5, 1.1f, fall(9.8)));
  EXPECT_TRUE(ok.pass) << ok.ToJson().dump(2);
  // 1.2 g: contact 1/sqrt(1.2) sooner, -8.7%.
  const Reconciliation r = Reconcile(p, Synthetic(400, 2e-5, 1.1f, fall(9.8 * 1.2)));
  EXPECT_FALSE(r.pass);
  EXPECT_NEAR(*Row(r, "contact_time").gap, 1 / std::sqrt(1.2) - 1, 0.005);
  EXPECT_NE(Row(r, "contact_time").hint.find("buoyancy"), std::string::npos);
}

// A 5x5x5 simple-cubic liquid lattice of spacing d (cu) around (10, 10, 10).
SiberneticConfig LiquidLattice(float d) {
  SiberneticConfig c = Box();
  for (int x = -2; x <= 2; ++x)
    for (int y = -2; y <= 2; ++y)
      for (int z = -2; z <= 2; ++z) AddParticle(&c, 10 + x * d, 10 + y * d, 10 + z * d, 1.1f);
  return c;
}

TEST(HydrostaticDensity, StartingLatticeAtR0IsUnderDense) {
  const Prediction p = Predict(LiquidLattice(1.67f), {}, {});
  // At d = h/2 the centre sees 6 neighbours at d, 12 at sqrt(2)d, 8 at sqrt(3)d (the 6 at 2d = h
  // are not < h), no self term: sum (h^2 - r^2)^3 = (6*(3/4)^3 + 12*(1/2)^3 + 8*(1/4)^3) h^6 =
  // 4.15625 h^6, rho = 2e-12 * 315 * 4.15625 / (64 pi (3.34 * 7.39999905e-6 m)^3) = 862.537.
  EXPECT_NEAR(Value(p, "initial_bulk_density"), 862.537, 0.05);
  // The spacing where the same 32-neighbour sum gives rho0 = 1000 (bisection, by hand 1.606425).
  EXPECT_NEAR(Value(p, "rest_lattice_spacing"), 1.606425, 1e-4);
  ASSERT_FALSE(p.notes.empty());
  EXPECT_NE(p.notes[0].find("under-dense"), std::string::npos);
  EXPECT_NEAR(Value(Predict(LiquidLattice(1.606425f), {}, {}), "initial_bulk_density"), 1000.0,
              0.05);
}

TEST(HydrostaticDensity, SinkingUnderDenseColumnIsExplained) {
  const Prediction p = Predict(LiquidLattice(1.67f), {}, {});
  Trajectory t;
  t.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  t.type.assign(125, 1.1f);
  for (int f = 0; f < 10; ++f) {  // every particle 1 cu lower from frame 1 on
    t.time_s.push_back(f * 1e-3);
    for (const auto& row : LiquidLattice(1.67f).position)
      t.positions.insert(t.positions.end(), {row[0], row[1] - (f > 0 ? 1.0f : 0.0f), row[2]});
  }
  const Reconciliation r = Reconcile(p, t);
  EXPECT_FALSE(r.pass);
  EXPECT_NEAR(*Row(r, "centroid_equilibrium").gap, -1.0, 1e-5);
  EXPECT_NE(Row(r, "centroid_equilibrium").hint.find("under-dense"), std::string::npos);
}

}  // namespace
}  // namespace owval::predict

namespace owval::predict {
namespace {

TEST(ChangedConstants, SourceAndPeriodFollowTheCallersValue) {
  engine::PhysicsConstants k;
  k.elasticity_coefficient = 5.55e8;
  const Prediction p = Predict(OneSprig(), k, {});
  // omega = sqrt(5.55e8 * 0.25) = 11779.22 rad/s, omega*dt/2 = 0.1177922;
  // T = 2*pi / (1e5 * asin(0.1177922)) = 0.5321743 ms.
  EXPECT_NEAR(Value(p, "zero_crossing_period"), 0.5321743e-3, 1e-10);
  std::string source;
  for (const PredictionInput& input : p.inputs)
    if (input.name == "elasticity_coefficient") source = input.source;
  EXPECT_NE(source.find("set by the caller"), std::string::npos) << source;
  ASSERT_FALSE(p.notes.empty());
  EXPECT_NE(p.notes.back().find("elasticity_coefficient"), std::string::npos);
}

}  // namespace
}  // namespace owval::predict
