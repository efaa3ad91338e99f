#include "owval/pipeline/checklist_request.hpp"

#include <algorithm>

#include "owval/backends/registry.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/json_file.hpp"
#include "owval/pipeline/pipeline.hpp"
#include "owval/scenarios/scenario.hpp"

namespace owval::pipeline {
namespace {

// The caller's registry entry for item 6's rerun. The registry file must not lie inside the
// directory under review: its commands would be the pull request's (docs/checklist.md, item 6).
backends::Backend CallerFitBackend(const ChecklistRequest& r) {
  const backends::RegistryOptions where = backends::RegistryOptionsFromEnvironment(r.backends_file);
  const std::filesystem::path file = backends::RegistryFile(where);
  if (!file.empty()) {
    const std::filesystem::path dir = std::filesystem::weakly_canonical(r.directory),
                                registry = std::filesystem::weakly_canonical(file);
    const auto [d, f] = std::mismatch(dir.begin(), dir.end(), registry.begin(), registry.end());
    if (d == dir.end())
      throw InputError(file.string(), 0,
                       "--fit-backend: the backends file lies inside the directory under review; "
                       "give the reviewer's own with --backends FILE");
  }
  return backends::LoadRegistry(where).Find(r.fit_backend);
}

}  // namespace

ci::ChecklistReport CheckDirectory(const ChecklistRequest& r) {
  ci::ChecklistOptions options;
  const compare::ParityOptions parity =
      scenarios::ParityOptionsFrom(r.scenario, r.manifest, r.data_dir);
  options.gates = parity.gates;
  if (!r.scenario.empty() || !r.manifest.empty()) options.track = parity.track;
  options.git_range = r.git_range;
  options.fit_rerun_tolerance = r.fit_rerun_tolerance;
  if (!r.fit_backend.empty()) options.fit_backend = CallerFitBackend(r);
  if (!r.markdown.empty()) {
    CheckOutputPath(r.markdown);
    std::vector<std::filesystem::path> inputs = ci::EvidenceFiles(r.directory);
    inputs.insert(inputs.end(), {r.manifest, r.reference});
    if (!r.fit_backend.empty())  // read for --fit-backend: `--markdown` over it replaced it
      inputs.push_back(
          backends::RegistryFile(backends::RegistryOptionsFromEnvironment(r.backends_file)));
    CheckOutputIsNotAnInput(r.markdown, inputs);
  }
  ScenarioReference reference;  // its temporary file lives until the checklist is done
  if (!r.scenario.empty()) {
    reference = MakeScenarioReference(r.scenario, r.data_dir);
    options.caller_reference = reference.file;
    options.caller_reference_source = r.scenario + "'s " + reference.source;
    options.scenario_prediction = MakeScenarioPrediction(r.scenario, r.data_dir);
    options.scenario_configuration = scenarios::ResolveConfig(r.scenario, r.data_dir);
    const nlohmann::json& manifest = scenarios::LoadScenario(r.scenario, r.data_dir).manifest;
    if (manifest.contains("fit") && manifest["fit"].is_object())
      options.scenario_fit_targets = manifest["fit"].value("targets", nlohmann::json::array());
  } else if (!r.reference.empty()) {
    options.caller_reference = r.reference;
    options.caller_reference_source = r.reference;
  }
  // The caller's manifest fixes the fit's targets as a named scenario's does (it wins, as its
  // gates do): with --reference and --manifest, a target weighted down until a bad fit
  // converged passed item 6.
  if (!r.manifest.empty()) {
    const nlohmann::json manifest = ReadJsonFile(r.manifest);
    if (manifest.is_object() && manifest.contains("fit") && manifest["fit"].is_object())
      options.scenario_fit_targets = manifest["fit"].value("targets", nlohmann::json::array());
  }
  const ci::ChecklistReport report = ci::RunChecklist(r.directory, options);
  if (!r.markdown.empty()) WriteFileAtomically(r.markdown, report.ToMarkdown());
  return report;
}

}  // namespace owval::pipeline
