// Every predictor against values computed by hand from its formula, and reconciliation against
// Sibernetic's own one_sprig run and against constructed signals with known defects.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/predict/predict.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::predict {
namespace {
namespace fs = std::filesystem;

using engine::Row4;
using engine::SiberneticConfig;

constexpr double kScale = 7.39999905e-06;  // m per cu (Sibernetic's simulationScale)
const fs::path kBundledOneSprig =
    fs::path(OWVAL_SOURCE_DIR) / "reference_trajectories/one_sprig/position_buffer.txt";

const nlohmann::json& Quantity(const nlohmann::json& p, const std::string& name) {
  for (const auto& q : p["predictions"])
    if (q["quantity"] == name) return q;
  throw std::runtime_error("no quantity " + name);
}
double Value(const nlohmann::json& p, const std::string& name) {
  return Quantity(p, name)["value"].get<double>();
}
const nlohmann::json& Row(const nlohmann::json& r, const std::string& name) {
  for (const auto& row : r["rows"])
    if (row["quantity"] == name) return row;
  throw std::runtime_error("no row " + name);
}

void AddParticle(SiberneticConfig* c, float x, float y, float z, float type) {
  c->position.push_back({x, y, z, type});
  c->velocity.push_back({0, 0, 0, 0});
}

// Springs of one elastic particle: its 32 connection rows, empty slots -1.
void AddSprings(SiberneticConfig* c, const std::vector<std::pair<int, float>>& springs) {
  for (int slot = 0; slot < engine::kConnectionSlots; ++slot) {
    const bool used = slot < int(springs.size());
    c->connection.push_back(
        {used ? float(springs[slot].first) : -1.0f, used ? springs[slot].second : -1.0f, 0, 0});
  }
  for (int m = 0; m < engine::kMembraneSlotsPerParticle; ++m) c->particle_mem_index.push_back(-1);
}

// Sibernetic's one_sprig: particle 0 (type 2.1) at y = 20.04 on a 14.195 cu spring to a wall
// particle (type 3) at y = 32.565.
SiberneticConfig OneSprig(float start_y = 20.04f) {
  SiberneticConfig c;
  c.source = "one_sprig (test)";
  c.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  AddParticle(&c, 17.535f, start_y, 17.535f, 2.1f);
  AddParticle(&c, 17.535f, 32.565f, 17.535f, 3.0f);
  AddSprings(&c, {{1, 14.195f}});
  return c;
}

TEST(HarmonicSpring, MatchesHandComputedValues) {
  const nlohmann::json p = Predict(OneSprig(), {}, {});
  EXPECT_EQ(p["predictor"], "harmonic_spring");
  // omega = sqrt(3e8 * 0.25) = 8660.254 rad/s, omega*dt/2 = 0.0866025;
  // T = 2*pi / (1e5 * asin(0.0866025)) = 0.7246109 ms; continuous 2*pi/omega = 0.7255197 ms.
  EXPECT_NEAR(Value(p, "zero_crossing_period"), 0.7246109e-3, 1e-10);
  EXPECT_NEAR(Value(p, "period_continuous"), 0.7255197e-3, 1e-10);
  // sag = 9.8 / 7.5e7 / 7.39999905e-6 = 0.0176577 cu; y_eq = 32.565 - 14.195 - sag.
  EXPECT_NEAR(Value(p, "gravity_sag"), 0.0176577, 1e-6);
  EXPECT_NEAR(Value(p, "equilibrium"), 18.352342, 2e-5);
  // A = (20.04 - 18.352342) / sqrt(1 - 0.0866025^2) = 1.694022.
  EXPECT_NEAR(Value(p, "half_amplitude"), 1.694022, 2e-5);
  EXPECT_NEAR(Quantity(p, "half_amplitude")["value_si"].get<double>(), 1.694022 * kScale, 1e-9);
  EXPECT_EQ(p["track"]["particle"], 0);
  EXPECT_EQ(p["track"]["axis"], "y");
}

TEST(HarmonicSpring, MeetsTheAcceptanceAgainstSiberneticsMeasurement) {
  const nlohmann::json p = Predict(OneSprig(), {}, {});
  EXPECT_LT(std::abs(Value(p, "zero_crossing_period") / 0.7246e-3 - 1), 0.003);
  EXPECT_LT(std::abs(Value(p, "half_amplitude") / 1.694 - 1), 0.01);
  EXPECT_LT(std::abs(Value(p, "equilibrium") - 18.352), 0.01);
}

TEST(HarmonicSpring, InputsNameTheirSource) {
  const nlohmann::json p = Predict(OneSprig(), {}, {});
  bool rest_length_from_config = false, k_from_default = false;
  for (const auto& i : p["inputs"]) {
    const std::string source = i["source"];
    if (i["name"] == "rest_length")
      rest_length_from_config = source.find("[connection] row 0") != std::string::npos;
    if (i["name"] == "elasticity_coefficient")
      k_from_default = source.find("default constant") != std::string::npos;
  }
  EXPECT_TRUE(rest_length_from_config);
  EXPECT_TRUE(k_from_default);
}

TEST(HarmonicSpring, OmittingTheQuarterFactorHalvesThePeriod) {
  PredictOptions o;
  o.omit_quarter_factor = true;
  const nlohmann::json p = Predict(OneSprig(), {}, o);
  // omega = sqrt(3e8) = 17320.5 rad/s: T = 2*pi / (1e5 * asin(0.173205)) = 0.3609304 ms.
  EXPECT_NEAR(Value(p, "zero_crossing_period"), 0.3609304e-3, 1e-10);
  EXPECT_TRUE(p["omit_quarter_factor"].get<bool>());
}

TEST(FreeFall, ContactTimeMatchesHandComputedValues) {
  SiberneticConfig c;
  c.source = "free_fall (test)";
  c.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  AddParticle(&c, 16.7f, 25.0f, 16.7f, 1.1f);
  AddParticle(&c, 16.7f, 0.835f, 16.7f, 3.0f);
  AddParticle(&c, 16.7f, 32.565f, 16.7f, 3.0f);
  const nlohmann::json p = Predict(c, {}, {});
  EXPECT_EQ(p["predictor"], "free_fall");
  // Contact at 0.835 + 1.67 = 2.505 cu; drop (25 - 2.505) * 7.4e-6 m = 1.66463e-4 m.
  EXPECT_NEAR(Value(p, "contact_height"), 2.505, 1e-5);
  // Continuous sqrt(2 * drop / 9.8) = 5.828554 ms; semi-implicit Euler n(n+1)/2 * g dt^2 = drop
  // gives n = 290.928 steps = 5.818562 ms.
  EXPECT_NEAR(Value(p, "contact_time_continuous"), 5.828554e-3, 2e-9);
  EXPECT_NEAR(Value(p, "contact_time"), 5.818562e-3, 2e-9);
}

// Two worm-body beads (type 2.1) below a wall anchor at y = 32.565: bead 0 hangs 4 cu below it
// (spring factor 0.25: the anchor is not worm body), bead 1 4 cu below bead 0 (full stiffness).
SiberneticConfig TwoBeadChain() {
  SiberneticConfig c;
  c.source = "chain (test)";
  c.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  AddParticle(&c, 17.535f, 28.565f, 17.535f, 2.1f);
  AddParticle(&c, 17.535f, 24.565f, 17.535f, 2.1f);
  AddParticle(&c, 17.535f, 32.565f, 17.535f, 3.0f);
  AddSprings(&c, {{2, 4.0f}, {1, 4.0f}});
  AddSprings(&c, {{0, 4.0f}});
  return c;
}

TEST(HangingChain, StaticSagMatchesHandComputedValues) {
  const nlohmann::json p = Predict(TwoBeadChain(), {}, {});
  EXPECT_EQ(p["predictor"], "hanging_chain");
  // Bead 1: k (y0 - y1 - 4) = g/s  →  y1 = y0 - 4 - 9.8/(3e8 * 7.4e-6) = y0 - 4.0044144.
  // Bead 0: k/4 (32.565 - y0 - 4) - k (y0 - y1 - 4) = g/s  →  y0 = 28.565 - 2*9.8/(7.5e7 * s)
  //         = 28.565 - 0.0353153 = 28.5296847;  y1 = 24.5252703.
  const nlohmann::json& eq = Quantity(p, "equilibrium");
  EXPECT_NEAR(eq["value"].get<double>(), 24.5252703, 2e-5);
  EXPECT_NEAR(eq["beads"][0]["equilibrium_y_cu"].get<double>(), 28.5296847, 2e-5);
  EXPECT_NEAR(Value(p, "tip_sag"), 24.565 - 24.5252703, 2e-5);
  EXPECT_EQ(p["track"]["particle"], 1);
}

TEST(HangingChain, OneBeadAgreesWithTheHarmonicSpring) {
  PredictOptions chain;
  chain.predictor = "hanging_chain";
  const nlohmann::json c = Predict(OneSprig(), {}, chain);
  const nlohmann::json s = Predict(OneSprig(), {}, {});
  EXPECT_NEAR(Value(c, "equilibrium"), Value(s, "equilibrium"), 1e-6);
  EXPECT_NEAR(Value(c, "fundamental_period"), Value(s, "zero_crossing_period"), 1e-12);
}

TEST(HydrostaticColumn, PressureProfileMatchesHandComputedValues) {
  SiberneticConfig c;
  c.source = "column (test)";
  c.box = {0, 3.34f, 0, 10.02f, 0, 3.34f};
  for (int layer = 0; layer < 3; ++layer)  // y = 2.505, 4.175, 5.845
    AddParticle(&c, 1.67f, 0.835f + 1.67f * float(layer + 1), 1.67f, 1.1f);
  AddParticle(&c, 1.67f, 0.835f, 1.67f, 3.0f);
  const nlohmann::json p = Predict(c, {}, {});
  EXPECT_EQ(p["predictor"], "hydrostatic_column");
  // Surface 5.845 + 0.835 = 6.68 cu; bottom layer depth 4.175 cu;
  // p = 1000 * 9.8 * 4.175 * 7.39999905e-6 = 0.302770 Pa.
  const nlohmann::json& pressure = Quantity(p, "bottom_pressure");
  EXPECT_NEAR(pressure["value"].get<double>(), 0.302770, 1e-5);
  ASSERT_EQ(pressure["profile"].size(), 3u);
  EXPECT_NEAR(pressure["profile"][2]["pressure_pa"].get<double>(), 1000 * 9.8 * 0.835 * kScale,
              1e-7);
  // Centroid 4.175 cu, gated at 1% of the 5.01 cu column.
  const nlohmann::json& centroid = Quantity(p, "centroid_equilibrium");
  EXPECT_NEAR(centroid["value"].get<double>(), 4.175, 1e-5);
  EXPECT_NEAR(centroid["tolerance"].get<double>(), 0.0501, 1e-5);
  EXPECT_EQ(p["track"]["group"], "liquid");
}

TEST(Predict, RefusesAConfigurationWithNoPredictor) {
  SiberneticConfig c = OneSprig();
  AddParticle(&c, 5, 5, 5, 1.1f);  // liquid next to the spring
  EXPECT_THROW(Predict(c, {}, {}), InputError);
  PredictOptions o;
  o.predictor = "free_fall";
  EXPECT_THROW(Predict(OneSprig(), {}, o), InputError);
}

TEST(Reconcile, OneSprigPredictionPassesOnSiberneticsRun) {
  const Trajectory t = ReadTrajectory(kBundledOneSprig);
  const nlohmann::json r = Reconcile(Predict(OneSprig(), {}, {}), t);
  EXPECT_TRUE(r["pass"].get<bool>()) << r.dump(2);
  EXPECT_LT(std::abs(Row(r, "zero_crossing_period")["gap"].get<double>()), 1e-4);
  EXPECT_LT(std::abs(Row(r, "equilibrium")["gap"].get<double>()), 1e-3);
  EXPECT_TRUE(Row(r, "gravity_sag")["pass"].is_null());  // informative, never gated
}

TEST(Reconcile, WithoutTheQuarterFactorFailsAndNamesIt) {
  PredictOptions o;
  o.omit_quarter_factor = true;
  const nlohmann::json r = Reconcile(Predict(OneSprig(), {}, o), ReadTrajectory(kBundledOneSprig));
  EXPECT_FALSE(r["pass"].get<bool>());
  const nlohmann::json& period = Row(r, "zero_crossing_period");
  EXPECT_NEAR(period["gap"].get<double>(), 1.0, 0.02);  // measured = 2x predicted
  EXPECT_NE(period["hint"].get<std::string>().find("0.25 factor"), std::string::npos);
  EXPECT_NE(ReconcileMarkdown(r).find("0.25 factor"), std::string::npos);
}

TEST(Reconcile, ToleranceOverrideGates) {
  ReconcileOptions o;
  o.tolerances["zero_crossing_period"] = 0;  // any gap fails
  const nlohmann::json r =
      Reconcile(Predict(OneSprig(), {}, {}), ReadTrajectory(kBundledOneSprig), o);
  EXPECT_FALSE(Row(r, "zero_crossing_period")["pass"].get<bool>());
  EXPECT_FALSE(r["pass"].get<bool>());
}

// A trajectory of particle 0 (type 2.1) and a wall particle with y(t) given per frame.
template <typename F>
Trajectory Synthetic(int frames, double dt, F y) {
  Trajectory t;
  t.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  t.time_step_s = dt;
  t.type = {2.1f, 3.0f};
  for (int f = 0; f < frames; ++f) {
    t.time_s.push_back(f * dt);
    t.positions.insert(t.positions.end(), {17.535f, float(y(f * dt)), 17.535f});
    t.positions.insert(t.positions.end(), {17.535f, 32.565f, 17.535f});
  }
  return t;
}

TEST(Reconcile, DampedOscillationPointsToViscousCoupling) {
  const nlohmann::json p = Predict(OneSprig(), {}, {});
  const double omega = 2 * M_PI / Value(p, "zero_crossing_period");
  const double y_eq = Value(p, "equilibrium"), a = Value(p, "half_amplitude");
  // Decays by e^-0.35 per period: the cycle amplitude averages well below the prediction.
  const Trajectory t = Synthetic(1000, 2e-5, [&](double s) {
    return y_eq + a * std::exp(-0.35 * s * omega / (2 * M_PI)) * std::cos(omega * s);
  });
  const nlohmann::json r = Reconcile(p, t);
  EXPECT_FALSE(r["pass"].get<bool>());
  EXPECT_NE(Row(r, "half_amplitude")["hint"].get<std::string>().find("viscous"), std::string::npos)
      << r.dump(2);
}

TEST(Reconcile, FreeFallFasterThanPredictedPointsToBuoyancy) {
  SiberneticConfig c;
  c.source = "free_fall (test)";
  c.box = {0, 33.4f, 0, 33.4f, 0, 33.4f};
  AddParticle(&c, 16.7f, 25.0f, 16.7f, 1.1f);
  AddParticle(&c, 16.7f, 0.835f, 16.7f, 3.0f);
  const nlohmann::json p = Predict(c, {}, {});
  auto fall = [](double g) { return [g](double s) { return 25.0 - 0.5 * g * s * s / kScale; }; };
  Trajectory exact = Synthetic(400, 2e-5, fall(9.8));
  exact.type[0] = 1.1f;
  const nlohmann::json ok = Reconcile(p, exact);
  EXPECT_TRUE(ok["pass"].get<bool>()) << ok.dump(2);
  Trajectory fast = Synthetic(400, 2e-5, fall(9.8 * 1.2));
  fast.type[0] = 1.1f;
  const nlohmann::json r = Reconcile(p, fast);
  EXPECT_FALSE(r["pass"].get<bool>());
  EXPECT_NE(Row(r, "contact_time")["hint"].get<std::string>().find("buoyancy"), std::string::npos);
}

TEST(Reconcile, RefusesAPredictionWithoutTrack) {
  nlohmann::json p = Predict(OneSprig(), {}, {});
  p.erase("track");
  EXPECT_THROW(Reconcile(p, ReadTrajectory(kBundledOneSprig)), InputError);
}

}  // namespace
}  // namespace owval::predict
