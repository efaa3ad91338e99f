#pragma once
// What the checklist's items read (Evidence), shared by checklist.cpp and the fit history's item
// (fit_history_check.cpp).
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "owval/ci/checklist.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"

namespace owval::ci::internal {

// What every item's check may read: the directory, the caller's options and the two
// trajectories, read frame by frame (issue 16: memory O(particles) whatever their length), each
// opened once; null when missing or unreadable.
struct Evidence {
  std::filesystem::path dir;
  ChecklistOptions options;
  // dir's reference.* and candidate.* (internal::RunFile: "" when absent), resolved once.
  std::filesystem::path reference_file, candidate_file;
  std::unique_ptr<FrameSource> reference, candidate;
  // The tracked scalar of every check: the caller's, never frames.json's (a pull request must
  // not pick the particle that happens to agree), else the default particle 0 y.
  Track track;
  std::string track_source;
  // options.caller_reference, opened before any item (unreadable: InputError, exit 2).
  std::unique_ptr<FrameSource> caller_reference;
  // Item 6's rerun judged at DD001's tolerance as well, when the caller's is looser: what
  // ChecklistReport::loosened_fit_rerun says of it ("" when no rerun was made).
  std::string rerun_at_default_tolerance;
  // fit/history.json as FitHistory read it, once for items 6 and 8, or why it could not.
  std::optional<nlohmann::json> fit_history;
  std::exception_ptr fit_history_unreadable;
};

using Check = void (*)(Evidence& e, ChecklistItem* item);

// Item 6: fit/history.json's claims recomputed from its own numbers, its targets measured again on
// the directory's reference, and its best iterate rerun (fit_history_check.cpp).
void CheckFitHistory(Evidence& e, ChecklistItem* item);

// fit/history.json, read once for items 6 and 8; throws why it cannot be read.
const nlohmann::json& FitHistory(Evidence& e);

}  // namespace owval::ci::internal
