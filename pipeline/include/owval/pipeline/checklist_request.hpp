#pragma once
// `owval checklist DIR` as a library call: the gates and track of a built-in scenario or a
// manifest (else DD001's defaults), the caller's reference (the scenario's own run, or a trusted
// trajectory file), the scenario's own prediction, and the Markdown output checked before any
// work starts (never one of the directory's evidence files) and written when the report is done.
#include <filesystem>
#include <string>

#include "owval/ci/checklist.hpp"

namespace owval::pipeline {

struct ChecklistRequest {
  std::string directory;  // the PR artifact directory (docs/checklist.md)
  std::string scenario;   // built-in scenario: its track, gates, reference and prediction
  std::string manifest;   // or a manifest: its track and gates
  std::string reference;  // or a trajectory the directory's reference must be
  std::string git_range;  // BASE..HEAD: prediction.json committed before the trajectories
  std::string markdown;   // also write the Markdown comment here ("": no)
  // Item 6's rerun of a fit of a named backend: the caller's registry entry `fit_backend` of
  // `backends_file` (else ./owval-backends.json, else the XDG file; never a file inside the
  // directory under review), and the relative tolerance of the rerun's residuals.
  std::string backends_file, fit_backend;
  double fit_rerun_tolerance = 1e-9;
  std::filesystem::path data_dir;
};

ci::ChecklistReport CheckDirectory(const ChecklistRequest& request);

}  // namespace owval::pipeline
