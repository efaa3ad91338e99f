// RerunBestIterate's reading of a history's "simulation" record (fit_record.cpp): a field of
// another JSON type is "not verified" naming the field, never nlohmann's own message (found by
// fuzz/fuzz_history.cpp: a backend record whose "name" was a number reached the checklist's
// report as "[json.exception.type_error.302] type must be string, but is number").
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "owval/backends/registry.hpp"
#include "owval/sgd/fit_record.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::sgd {
namespace {

nlohmann::json BackendHistory() {
  return nlohmann::json::parse(R"({
    "simulation": {"kind": "backend", "name": "port", "command": "port -o {out}",
                   "configuration": {"file": "configuration.txt", "fnv1a64": "0"},
                   "duration_s": 0.0004, "time_step_s": 2e-05, "log_step": 20}})");
}

std::string NotVerified(const nlohmann::json& history) {
  backends::Backend reviewer;
  reviewer.name = "port";
  reviewer.kind = backends::BackendKind::kStore;
  FitRerunOptions options;
  options.backend = &reviewer;
  return RerunBestIterate(history, testing::TestScratch("fit"), options).not_verified;
}

TEST(FitRecord, ABackendRecordsNameMustBeAString) {
  nlohmann::json h = BackendHistory();
  EXPECT_EQ(NotVerified(h), "the fit's configuration configuration.txt is missing");
  h["simulation"]["name"] = 5;
  EXPECT_EQ(NotVerified(h), "simulation.name is not a string");
  h["simulation"].erase("name");  // optional: the report says '?'
  EXPECT_EQ(NotVerified(h), "the fit's configuration configuration.txt is missing");
}

}  // namespace
}  // namespace owval::sgd
