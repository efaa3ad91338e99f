#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/predict/predict.hpp"
#include "owval/scenarios/generators.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "prediction_parts.hpp"

namespace owval::predict {
namespace {
namespace fs = std::filesystem;

const fs::path kBundledOneSprig = owval::testing::kBundledOneSprig;

const nlohmann::json& Q(const nlohmann::json& prediction, const std::string& name) {
  for (const auto& q : prediction["predictions"])
    if (q["quantity"] == name) return q;
  throw std::runtime_error("no quantity " + name);
}
double V(const nlohmann::json& prediction, const std::string& name) {
  return Q(prediction, name)["value"];
}

// The prediction as prediction.json holds it: every check below also covers ToJson.
nlohmann::json PredictFor(const engine::SiberneticConfig& c, bool omit_quarter = false) {
  PredictOptions o;
  o.omit_quarter_factor = omit_quarter;
  return Predict(c, engine::PhysicsConstants{}, o).ToJson();
}

// Reconciles a prediction.json document (read back with FromJson), as reconcile.json holds it.
nlohmann::json ReconcileJson(const nlohmann::json& prediction, const Trajectory& t,
                             const ReconcileOptions& o = {}) {
  return Reconcile(Prediction::FromJson(prediction, "prediction.json"), t, o).ToJson();
}

// Hand values (Sibernetic's one_sprig meta.json theory check): k_eff = 0.25 * 3e8 = 7.5e7 s^-2,
// omega = 8660.254 rad/s, omega*dt/2 = 0.0866025; T = 2*pi/((2/dt)*asin(0.0866025)) =
// 0.7246109 ms (continuous 0.7255197 ms); sag = 9.8/7.5e7/7.4e-6 = 0.017658 cu;
// y_eq = 32.565 - 14.195 - 0.017658 = 18.352342; A = 1.687658/sqrt(1 - 0.0866025^2) = 1.69402.
TEST(HarmonicSpring, OneSprigMatchesHandComputedValues) {
  const nlohmann::json p = PredictFor(scenarios::OneSprig({}));
  EXPECT_EQ(p["predictor"], "harmonic_spring");
  EXPECT_NEAR(V(p, "zero_crossing_period"), 0.7246109e-3, 1e-10);
  EXPECT_NEAR(V(p, "period_continuous"), 0.7255197e-3, 1e-10);
  EXPECT_NEAR(V(p, "gravity_sag"), 0.017658, 1e-6);
  EXPECT_NEAR(V(p, "equilibrium"), 18.352342, 1e-5);
  EXPECT_NEAR(V(p, "half_amplitude"), 1.69402, 1e-5);
  EXPECT_NEAR(Q(p, "equilibrium")["value_si"].get<double>(), 18.352342 * 7.39999905e-6, 1e-10);
}

TEST(HarmonicSpring, InputsNameTheirConfigurationLines) {
  const nlohmann::json p = PredictFor(scenarios::OneSprig({}));
  std::string sources;
  for (const auto& i : p["inputs"])
    sources += i["name"].get<std::string>() + ": " + i["source"].get<std::string>() + "\n";
  // Sibernetic's one_sprig_test: anchor row 1180 on line 1189, the spring on line 4349.
  EXPECT_NE(sources.find("anchor_y: configuration line 1189 ([position] row 1180)"),
            std::string::npos)
      << sources;
  EXPECT_NE(sources.find("rest_length: configuration line 4349"), std::string::npos) << sources;
  EXPECT_NE(sources.find("spring_factor: sphFluid.cl: 0.25"), std::string::npos) << sources;
}

TEST(HarmonicSpring, WithoutTheQuarterFactorThePeriodHalves) {
  const nlohmann::json p = PredictFor(scenarios::OneSprig({}), true);
  // omega = sqrt(3e8) = 17320.5: T = 2*pi/((2/dt)*asin(0.173205)) = 0.3609304 ms.
  EXPECT_NEAR(V(p, "zero_crossing_period"), 0.3609304e-3, 1e-10);
  EXPECT_NEAR(V(p, "gravity_sag"), 0.017658 / 4, 1e-6);
}

TEST(HarmonicSpring, OnlyTwoWormBodyEndsGetFullStiffness) {
  const engine::PhysicsConstants k;
  const PredictOptions o;
  EXPECT_EQ(internal::SpringFactor(2.1f, 2.2f, k, o), 1.0);
  EXPECT_EQ(internal::SpringFactor(2.1f, 3.0f, k, o), 0.25);
  EXPECT_EQ(internal::SpringFactor(2.3f, 2.1f, k, o), 0.25);
  EXPECT_EQ(internal::SpringFactor(2.0f, 2.0f, k, o), 0.25);
}

// Start 25 cu, floor wall 0.835, contact where the wall enters the kernel support: 0.835 + 3.34 =
// 4.175; drop 20.825 cu = 1.541050e-4 m. Continuous t = sqrt(2*1.541050e-4/9.8) = 5.608030 ms;
// discrete n(n+1) = 2*drop/(g*dt^2) = 78624.99 -> n = 279.9019, t = 5.598039 ms.
TEST(FreeFall, ContactTimeMatchesHandComputedValues) {
  const nlohmann::json p = PredictFor(scenarios::FreeFall({}));
  EXPECT_EQ(p["predictor"], "free_fall");
  EXPECT_NEAR(V(p, "contact_height"), 4.175, 1e-5);
  EXPECT_NEAR(V(p, "contact_time_continuous"), 5.608030e-3, 2e-8);
  EXPECT_NEAR(V(p, "contact_time"), 5.598039e-3, 2e-8);
}

// Five 2.1 beads: the anchor spring (to a type-3 wall) carries all five beads at 0.25*k, bead
// springs carry 4,3,2,1 beads at full k: sag = (5*9.8/7.5e7 + 10*9.8/3e8)/7.4e-6 = 0.1324326 cu.
TEST(HangingChain, StaticSagMatchesHandComputedValue) {
  const nlohmann::json p = PredictFor(scenarios::HangingChain({}));
  EXPECT_EQ(p["predictor"], "hanging_chain");
  EXPECT_EQ(p["track"]["particle"], 4);
  EXPECT_NEAR(V(p, "tip_sag"), 0.1324326, 1e-6);
  EXPECT_NEAR(V(p, "equilibrium"), 32.565 - 4 - 16 - 0.1324326, 1e-5);
  // The first bead hangs by the anchor spring alone: 5*9.8/7.5e7/7.4e-6 = 0.0882883 cu.
  EXPECT_NEAR(Q(p, "equilibrium")["beads"][0]["equilibrium_y_cu"].get<double>(),
              32.565 - 4 - 0.0882883, 1e-5);
}

TEST(HangingChain, NonWormBodyBeadsAreFourTimesSofter) {
  // Every spring at 0.25*k: sag = 15*9.8/7.5e7/7.4e-6 = 0.2648649 cu.
  const nlohmann::json p = PredictFor(scenarios::HangingChain({{"elastic_type", 2.3}}));
  EXPECT_NEAR(V(p, "tip_sag"), 0.2648649, 1e-6);
}

TEST(HangingChain, OneBeadIsTheHarmonicSpring) {
  PredictOptions o;
  o.predictor = "hanging_chain";  // one bead on one spring would otherwise pick harmonic_spring
  const nlohmann::json p = Predict(scenarios::HangingChain({{"beads", 1}}), {}, o).ToJson();
  EXPECT_NEAR(V(p, "fundamental_period"), 0.7246109e-3, 1e-10);
  EXPECT_NEAR(V(p, "tip_sag"), 0.017658, 1e-6);
}

// 8 layers of liquid from y = 2.505 to 14.195: surface 15.03, bottom depth 12.525 cu;
// p = 1000*9.8*12.525*7.39999905e-6 = 0.9083129 Pa; centroid 8.35; 1% of height 13.36 = 0.1336.
TEST(HydrostaticColumn, PressureProfileMatchesHandComputedValues) {
  const nlohmann::json p = PredictFor(scenarios::LiquidColumn({}));
  EXPECT_EQ(p["predictor"], "hydrostatic_column");
  EXPECT_NEAR(V(p, "bottom_pressure"), 0.9083129, 1e-6);
  EXPECT_NEAR(V(p, "centroid_equilibrium"), 8.35, 1e-5);
  EXPECT_NEAR(Q(p, "centroid_equilibrium")["tolerance"].get<double>(), 0.1336, 1e-6);
  const nlohmann::json& profile = Q(p, "bottom_pressure")["profile"];
  ASSERT_EQ(profile.size(), 8u);
  EXPECT_NEAR(profile[7]["pressure_pa"].get<double>(), 1000 * 9.8 * 0.835 * 7.39999905e-6, 1e-8);
  EXPECT_EQ(p["track"]["group"], "liquid");
}

TEST(Predict, RefusesConfigurationsWithoutAPredictor) {
  engine::SiberneticConfig mixed = scenarios::HangingChain({});
  mixed.position.push_back({10, 10, 10, 1.1f});
  mixed.velocity.push_back({0, 0, 0, 0});
  EXPECT_THROW(PredictFor(mixed), InputError);
  PredictOptions wrong;
  wrong.predictor = "free_fall";
  EXPECT_THROW(Predict(scenarios::OneSprig({}), engine::PhysicsConstants{}, wrong), InputError);
}

TEST(Reconcile, OneSprigPredictionPassesAgainstSiberneticsRun) {
  const nlohmann::json r =
      ReconcileJson(PredictFor(scenarios::OneSprig({})), ReadTrajectory(kBundledOneSprig));
  EXPECT_TRUE(r["pass"].get<bool>()) << r.dump(2);
  for (const auto& row : r["rows"])
    if (row["quantity"] == "zero_crossing_period") {
      EXPECT_LT(std::abs(row["gap"].get<double>()), 1e-5);
    }
}

TEST(Reconcile, MissingQuarterFactorFailsAndIsNamed) {
  PredictOptions omit;
  omit.omit_quarter_factor = true;
  const Reconciliation typed =
      Reconcile(Predict(scenarios::OneSprig({}), {}, omit), ReadTrajectory(kBundledOneSprig));
  const nlohmann::json r = typed.ToJson();
  EXPECT_FALSE(r["pass"].get<bool>());
  const nlohmann::json& period = r["rows"][0];
  ASSERT_EQ(period["quantity"], "zero_crossing_period");
  EXPECT_NEAR(period["gap"].get<double>(), 1.0, 0.02);  // measured = 2x predicted
  EXPECT_NE(period["hint"].get<std::string>().find("0.25 factor"), std::string::npos);
  EXPECT_NE(ReconcileMarkdown(typed).find("0.25 factor"), std::string::npos);
}

TEST(Reconcile, ToleranceOptionsOverrideThePrediction) {
  const nlohmann::json p = PredictFor(scenarios::OneSprig({}));
  const Trajectory t = ReadTrajectory(kBundledOneSprig);
  ReconcileOptions strict;
  strict.tolerances["half_amplitude"] = 1e-9;
  EXPECT_FALSE(ReconcileJson(p, t, strict)["pass"].get<bool>());
  ReconcileOptions loose;
  loose.tolerance = 1.5;
  EXPECT_TRUE(
      ReconcileJson(PredictFor(scenarios::OneSprig({}), true), t, loose)["pass"].get<bool>());
}

TEST(Reconcile, RefusesAToleranceForAQuantityItDoesNotGate) {
  const nlohmann::json p = PredictFor(scenarios::OneSprig({}));
  const Trajectory t = ReadTrajectory(kBundledOneSprig);
  ReconcileOptions misspelt;
  misspelt.tolerances["equilibrum"] = 1e-3;
  EXPECT_THROW(ReconcileJson(p, t, misspelt), InputError);
  ReconcileOptions nameless;
  EXPECT_THROW(nameless.AddTolerance("=0.001"), InputError);
}

TEST(Reconcile, RefusesAPredictionWithoutTrackOrQuantities) {
  const Trajectory t = ReadTrajectory(kBundledOneSprig);
  EXPECT_THROW(ReconcileJson(nlohmann::json::object(), t), InputError);
  nlohmann::json p = PredictFor(scenarios::OneSprig({}));
  p["track"]["particle"] = 99999;
  EXPECT_THROW(ReconcileJson(p, t), InputError);
}

// Issue 18 item 12: an entry without "value" aborted on a nlohmann assertion; now every
// malformed field is one line naming the file and the field's path.
TEST(Prediction, FromJsonNamesTheFileAndTheMalformedField) {
  nlohmann::json p = PredictFor(scenarios::OneSprig({}));
  EXPECT_EQ(Prediction::FromJson(p, "p.json").ToJson(), p);  // the round trip is exact
  auto message = [](const nlohmann::json& j) {
    try {
      Prediction::FromJson(j, "p.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  nlohmann::json no_value = p;
  no_value["predictions"][1].erase("value");
  EXPECT_EQ(message(no_value), "p.json: \"predictions[1].value\": expected a finite number");
  nlohmann::json bad_kind = p;
  bad_kind["predictions"][0]["tolerance_kind"] = "loose";
  EXPECT_EQ(message(bad_kind),
            "p.json: \"predictions[0].tolerance_kind\": expected relative, absolute_cu or "
            "informative");
  nlohmann::json bad_note = p;
  bad_note["notes"] = {1};
  EXPECT_EQ(message(bad_note), "p.json: \"notes[0]\": expected a string");
  EXPECT_EQ(message(nlohmann::json::array()),
            "p.json: \"(top level)\": expected an object (owval predict -o FILE)");
}

TEST(Cli, PredictAndReconcileExitCodes) {
  const fs::path owval = fs::path(OWVAL_BINARY_DIR) / "owval";
  if (!fs::exists(owval)) GTEST_SKIP() << "owval not built";
  const fs::path dir = owval::testing::TestScratch();
  const std::string exe = owval.string() + " -q ";
  const std::string good = (dir / "owval_pred.json").string();
  const std::string bad = (dir / "owval_pred_noq.json").string();
  ASSERT_EQ(std::system((exe + "predict one_sprig -o " + good + " > /dev/null").c_str()), 0);
  ASSERT_EQ(std::system(
                (exe + "predict one_sprig --no-quarter-factor -o " + bad + " > /dev/null").c_str()),
            0);
  const std::string traj = " " + kBundledOneSprig.string() + " > /dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system((exe + "reconcile " + good + traj).c_str())), 0);
  EXPECT_EQ(WEXITSTATUS(std::system((exe + "reconcile " + bad + traj).c_str())), 1);
  EXPECT_EQ(WEXITSTATUS(std::system((exe + "predict no_such_thing 2> /dev/null").c_str())), 2);
  fs::remove(good);
  fs::remove(bad);
}

}  // namespace
}  // namespace owval::predict
