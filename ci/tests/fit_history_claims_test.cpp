// Item 6 recomputes fit/history.json's claims from its own numbers instead of taking
// "converged": true on trust, and then reruns the best iterate (docs/checklist.md): a history
// that only agrees with itself is not verified. The reruns of a real fit, and histories edited
// after it, are tested on the pipeline's directory (cli/tests/checklist_test.cpp) and on
// `owval fit`'s (pipeline/tests/fit_rerun_test.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "owval/ci/checklist.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

// A directory holding only fit/history.json; item 6 of its checklist.
ChecklistItem ItemSix(const std::string& name, const nlohmann::json& history,
                      const ChecklistOptions& options = {}) {
  const fs::path dir = owval::testing::TestScratch(name);
  fs::create_directories(dir / "fit");
  std::ofstream(dir / "fit/history.json") << history.dump(2);
  const ChecklistReport r = RunChecklist(dir, options);
  for (const ChecklistItem& i : r.items)
    if (i.number == 6) return i;
  throw std::runtime_error("no item 6");
}

// one_sprig's pipeline fit as it wrote it (reports/one_sprig/fit/history.json), trimmed.
nlohmann::json ConvergedFit() {
  return nlohmann::json::parse(R"({
    "schema": "owval.fit.history/1", "solver": "levenberg_marquardt", "loss_threshold": 1e-4,
    "converged": true, "stop_reason": "loss below threshold",
    "iterations": [
      {"iteration": 0, "loss": 0.13077667303336002,
       "residuals": [0.3616132018723555, 0.0035447517519681493]},
      {"iteration": 1, "loss": 0.0019326329159522996,
       "residuals": [0.04396057030647004, 0.00031807905024410453]},
      {"iteration": 2, "loss": 8.277120222159476e-07,
       "residuals": [0.0009097501778876778, 8.163090669981444e-06]}],
    "final": {"loss": 8.277120222159476e-07, "parameters": {"elasticity_coefficient": 2.99e8}}})");
}

// Numbers that agree with each other are what a forger writes first: without the record of
// what was simulated there is nothing to rerun, and the item fails.
TEST(FitHistoryClaims, ASelfConsistentHistoryWithoutItsSimulationIsNotVerified) {
  const ChecklistItem i = ItemSix("consistent", ConvergedFit());
  EXPECT_FALSE(i.pass) << i.detail;
  EXPECT_NE(i.detail.find("not verified: the history records no \"simulation\""), std::string::npos)
      << i.detail;
}

// A record whose evidence is not there (no configuration beside it, no reference to measure the
// targets on) cannot be rerun either.
TEST(FitHistoryClaims, AnEngineRecordWithoutItsEvidenceIsNotVerified) {
  nlohmann::json h = ConvergedFit();
  h["simulation"] = {{"kind", "engine"},
                     {"configuration", {{"file", "configuration.txt"}, {"fnv1a64", "0"}}}};
  const ChecklistItem i = ItemSix("no_configuration", h);
  EXPECT_FALSE(i.pass) << i.detail;
  EXPECT_NE(i.detail.find("; not verified: "), std::string::npos) << i.detail;
}

// A history may set its own loss_threshold; the caller's (DD001's 1e-4 by default) judges it.
TEST(FitHistoryClaims, AThresholdLoosenedByTheHistoryFails) {
  nlohmann::json h = ConvergedFit();
  h["iterations"].erase(2);  // stopped after iteration 1, loss 0.0019
  h["final"]["loss"] = 0.0019326329159522996;
  h["loss_threshold"] = 0.01;
  const ChecklistItem i = ItemSix("loose_threshold", h);
  EXPECT_FALSE(i.pass);
  EXPECT_NE(i.detail.find("is not below the caller's threshold 0.0001"), std::string::npos)
      << i.detail;
}

// An external command's runs cannot be rerun by owval: not verified, never passed on trust.
TEST(FitHistoryClaims, ACommandFitIsNotVerified) {
  nlohmann::json h = ConvergedFit();
  h["simulation"] = {{"kind", "command"}, {"command", "./metal_port {out}"}};
  const ChecklistItem i = ItemSix("command_fit", h);
  EXPECT_FALSE(i.pass) << i.detail;
  EXPECT_NE(i.detail.find("not verified: simulation.kind 'command'"), std::string::npos)
      << i.detail;
}

TEST(FitHistoryClaims, ConvergedOverALossAboveTheThresholdFails) {
  nlohmann::json h = ConvergedFit();
  h["iterations"].erase(2);  // stopped after iteration 1, loss 0.0019 > 1e-4
  h["final"]["loss"] = 0.0019326329159522996;
  const ChecklistItem i = ItemSix("above_threshold", h);
  EXPECT_FALSE(i.pass);
  EXPECT_NE(i.detail.find("is not below loss_threshold"), std::string::npos) << i.detail;
}

TEST(FitHistoryClaims, ALossItsResidualsDoNotMakeFails) {
  nlohmann::json h = ConvergedFit();
  h["iterations"][1]["loss"] = 1e-7;  // the residuals still say 0.0019
  h["iterations"][2]["loss"] = 1e-7, h["final"]["loss"] = 1e-7;
  const ChecklistItem i = ItemSix("forged_loss", h);
  EXPECT_FALSE(i.pass);
  EXPECT_NE(i.detail.find("iteration 1 claims loss 1e-07"), std::string::npos) << i.detail;
}

TEST(FitHistoryClaims, AFinalLossNoIterationReachedFails) {
  nlohmann::json h = ConvergedFit();
  h["final"]["loss"] = 1e-9;
  const ChecklistItem i = ItemSix("forged_final", h);
  EXPECT_FALSE(i.pass);
  EXPECT_NE(i.detail.find("is not the best iteration's"), std::string::npos) << i.detail;
}

TEST(FitHistoryClaims, LossesWithoutResidualsAreClaimedNotVerified) {
  nlohmann::json h = ConvergedFit();
  for (auto& it : h["iterations"]) it.erase("residuals");
  const ChecklistItem i = ItemSix("no_residuals", h);
  EXPECT_FALSE(i.pass);
  EXPECT_NE(i.detail.find("converged claimed, not verified"), std::string::npos) << i.detail;
}

// A field of another JSON type than the history's schema is named with what was expected, not
// reported in nlohmann's words ("[json.exception.type_error.302] type must be string, but is
// number"; found by fuzz/fuzz_history.cpp).
TEST(FitHistoryClaims, AFieldOfAnotherTypeIsNamedWithWhatWasExpected) {
  nlohmann::json h = ConvergedFit();
  h["converged"] = 1;
  EXPECT_EQ(ItemSix("converged_number", h).detail,
            (owval::testing::TestScratch("converged_number") / "fit/history.json").string() +
                ": converged: expected true or false");
  h = ConvergedFit();
  h["simulation"] = {{"kind", 5}};
  EXPECT_EQ(ItemSix("kind_number", h).detail,
            "fit/history.json: simulation.kind: expected a string");
  h["simulation"] = {{"kind", "engine"}};
  h["targets"] = {{{"metric", 5}, {"weight", 1}}};
  ChecklistOptions scenario;
  scenario.scenario_fit_targets = {{{"metric", "period"}, {"weight", 1}}};
  EXPECT_EQ(ItemSix("metric_number", h, scenario).detail,
            "fit/history.json: targets[0].metric: expected a string");
}

}  // namespace
}  // namespace owval::ci
