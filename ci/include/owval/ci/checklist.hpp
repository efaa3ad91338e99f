#pragma once
// The PR checklist bot (phase 8): judges a pull request's artifact directory item by item on the
// evidence, not on its presence: the candidate must pass the parity gates against the reference
// (recomputed from the two trajectories, whatever parity.json says), every sampled frame must be
// within the frame gate, the prediction is reconciled with the *reference* measurement, and the
// prediction's order before the runs is checked in the git history where one is given. Renders
// the verdict as a Markdown comment. File names and rules: docs/checklist.md.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/backends/registry.hpp"
#include "owval/compare/parity.hpp"
#include "owval/engine/config.hpp"
#include "owval/predict/prediction.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::ci {

struct ChecklistOptions {
  // Gate thresholds. They come from the caller (a scenario manifest or flags), never from files
  // in the directory under review: a pull request cannot loosen its own gates.
  compare::ParityGates gates;
  // The tracked scalar of the frame gates, from the caller (a scenario manifest or flags);
  // empty: particle 0 y. Never frames/frames.json's: a pull request cannot choose the particle
  // that happens to agree (frames.json must label this track, else item 5 fails).
  std::optional<Track> track;
  // The caller's reference, a trajectory file: a named scenario's own
  // (pipeline::MakeScenarioReference) or one the caller trusts (--reference). Item 2 holds the
  // directory's reference to it, frame for frame (both read frame by frame). Empty: item 2
  // fails, since a pull request could judge its candidate against a reference of its own making
  // (its candidate under another name).
  std::filesystem::path caller_reference;
  std::string caller_reference_source;  // what it is, for the report
  // The scenario's own prediction (its predictor on its configuration), when the caller names a
  // scenario: item 10 reconciles with its tolerances and needs its gated quantities and track,
  // so prediction.json cannot loosen or drop what it is judged on.
  std::optional<predict::Prediction> scenario_prediction;
  // The named scenario's configuration: item 6 holds the fit's recorded configuration
  // (fit/configuration.txt) to it, so a fit of another system cannot stand for the scenario's.
  std::optional<engine::SiberneticConfig> scenario_configuration;
  // The named scenario's (or the caller's --manifest's) "fit.targets" ({metric, weight}
  // objects): item 6 holds the history's targets to their metrics and weights, so a target
  // cannot be weighted down until a bad fit converges. Empty (null): not checked (neither
  // named, or the manifest has no fit).
  nlohmann::json scenario_fit_targets;
  // Item 6: the fit's best loss must be below this, whatever the history's own loss_threshold
  // says (a pull request cannot loosen its fit's convergence either). DD001's default.
  double fit_loss_threshold = 1e-4;
  // Item 6, a fit of a named backend (history kind "backend"): the registry entry the caller
  // names (--backends FILE --fit-backend NAME) its best iterate is rerun through, never the
  // command the history records (that would run the pull request's program on the reviewer's
  // machine). Empty: such a fit is "not verified".
  std::optional<backends::Backend> fit_backend;
  // Item 6: the rerun's residuals and loss must equal the best iteration's within this relative
  // tolerance (1e-12 absolute near 0). The engine reproduces its runs to the last bit; a port on
  // another substrate may need more, which the caller states (reported in the detail).
  double fit_rerun_tolerance = 1e-9;
  // "BASE..HEAD": item 1 checks in this range of the git history that prediction.json was
  // committed no later than the first trajectory. Empty: the order is reported as not checked.
  std::string git_range;
};

struct ChecklistItem {
  int number = 0;        // 1..10, as in the design notes
  std::string title;     // e.g. "side-by-side MP4"
  bool present = false;  // the artifact exists
  bool pass = false;     // it exists and its check passed
  std::string detail;    // what was measured, or why it failed
};

enum class Verdict {
  kReady,         // all ten items and the parity gate pass
  kIncomplete,    // only items 7-10 missing or failing: not blocking
  kNotReady,      // item 1, 4, 5 or 6 missing or failing, or the parity gate fails
  kUnreviewable,  // item 2 or 3 missing or failing (item 2 also without the caller's reference)
};
const char* VerdictName(Verdict verdict);

struct ChecklistReport {
  std::filesystem::path directory;
  std::vector<ChecklistItem> items;
  // The parity of the candidate against the reference, recomputed; empty when either trajectory
  // is missing or unreadable (then item 2 or 3 fails).
  std::optional<compare::ParityReport> parity;
  std::string parity_note;  // e.g. "parity.json is stale: it says pass, recomputed FAIL"
  // Not a gate: set when the candidate equals the reference at every paired frame (a perfect
  // port or a copy; the files cannot tell), with the candidate's recorded producer.
  std::string candidate_note;
  // The tracked scalar moves in the reference; a still one (a wall particle) fails the parity
  // gate, whose frame gate it would pass with any candidate that leaves it alone.
  bool tracked_moves = false;
  // The caller's thresholds looser than DD001's defaults (compare::LoosenedThresholds), and when
  // there are any, the gates the candidate fails with those put back to the defaults: a
  // candidate that passes only because its caller loosened the gates is not ready, and the
  // report says which gates were loosened either way.
  std::vector<std::string> loosened_thresholds;
  std::string failed_at_default_thresholds;  // "liquid.worst_particle"; empty: passes them too
  // Item 6's rerun tolerance when the caller's (--fit-rerun-tolerance) is looser than DD001's,
  // with what the rerun gave at the default: "fit_rerun_tolerance 1e-06 (caller; default 1e-09):
  // at the default the rerun does NOT reproduce ...". Reported, not blocking: a port on another
  // substrate need not reproduce its own runs to the last bit, and the rerun's own loss is
  // judged against the caller's threshold whatever the tolerance. Empty: not loosened.
  std::string loosened_fit_rerun;
  Verdict verdict = Verdict::kNotReady;
  std::vector<std::string> blocking;  // what makes the verdict what it is, e.g. "item 5 (...)"

  int exit_code() const;  // 0 ready or incomplete, 1 otherwise
  bool parity_pass() const {
    return parity && parity->pass() && tracked_moves && failed_at_default_thresholds.empty();
  }
  std::string ToMarkdown() const;
  nlohmann::json ToJson() const;
};

ChecklistReport RunChecklist(const std::filesystem::path& directory,
                             const ChecklistOptions& options = {});

// The files of `directory` the checklist may read (every regular file in it, recursively, at most
// 10,000), so that an output such as `--markdown DIR/candidate.txt` is refused before it
// replaces the evidence it reports on.
std::vector<std::filesystem::path> EvidenceFiles(const std::filesystem::path& directory);

// InputError unless `git_range` is BASE..HEAD and git can read it in `directory`'s repository.
void CheckGitRange(const std::filesystem::path& directory, const std::string& git_range);

// Whether prediction.json was committed no later than the first trajectory in `git_range`
// (BASE..HEAD) of the repository holding `directory`; runs git. `detail` says what was found.
// Throws InputError when git cannot read the range.
bool PredictionCommittedFirst(const std::filesystem::path& directory, const std::string& git_range,
                              std::string* detail);

}  // namespace owval::ci
