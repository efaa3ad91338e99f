#pragma once
// `owval gradcheck` as a library call: the XPBD backward kernels against central differences
// (engine::RunGradCheck), with demo1's defaults for the end-to-end test (the shared reference's
// configuration, and its OpenCL run as the loss's reference: the fit's centroid loss), and
// fd_tests.json (checklist item 7) written when asked, its path checked before any test runs.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "owval/engine/gradient.hpp"

namespace owval::pipeline {

struct GradCheckRequest {
  engine::GradCheckOptions options;  // "" end_to_end_config: shared_reference/demo1's
  // The end-to-end loss: the elastic and liquid centroids (those the run holds) against this run
  // ("": with the default configuration, demo1's OpenCL run; else the model's own trajectory at
  // shifted parameters).
  std::string reference;
  std::string output;                      // fd_tests.json ("": not written)
  std::filesystem::path shared_reference;  // Sibernetic's reference runs (../shared/reference)
};

struct GradCheckResult {
  engine::GradCheckSummary summary;
  nlohmann::json json;  // fd_tests.json's content

  bool pass() const { return summary.pass; }
  const nlohmann::json& ToJson() const { return json; }
  // "pass NAME: fd X, analytic Y, relative error Z" per test, then the brief report.
  std::string ToText() const;
};

GradCheckResult RunGradCheckRequest(GradCheckRequest request);

}  // namespace owval::pipeline
