#pragma once
// The PR checklist bot (phase 8): checks a pull request's artifact directory item by item, for
// real (files parse, the video decodes, the frames' numbers agree with the trajectories, the fit
// converged), and renders the verdict as a Markdown comment. File names: docs/checklist.md.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace owval::ci {

struct ChecklistItem {
  int number = 0;        // 1..10, as in the design notes
  std::string title;     // e.g. "side-by-side MP4"
  bool present = false;  // the artifact exists
  bool pass = false;     // it exists and its check passed
  std::string detail;    // what was measured, or why it failed
};

enum class Verdict {
  kReady,         // all ten items pass
  kIncomplete,    // only items 7-10 missing or failing: not blocking
  kNotReady,      // item 1, 4, 5 or 6 missing or failing
  kUnreviewable,  // item 2 or 3 missing or failing
};
const char* VerdictName(Verdict verdict);

struct ChecklistReport {
  std::filesystem::path directory;
  std::vector<ChecklistItem> items;
  Verdict verdict = Verdict::kNotReady;
  int exit_code() const;  // 0 ready or incomplete, 1 otherwise
  std::string ToMarkdown() const;
  nlohmann::json ToJson() const;
};

ChecklistReport RunChecklist(const std::filesystem::path& directory);

// Facts about an MP4 read back through libavformat/libavcodec (frames decoded, not guessed).
struct VideoInfo {
  std::string codec;
  int width = 0, height = 0;
  std::size_t decoded_frames = 0;
  double duration_s = 0;
};
// Throws InputError when the file is missing or does not decode.
VideoInfo ProbeVideo(const std::filesystem::path& path);

// Width and height of a PNG; throws InputError when it does not decode.
std::pair<int, int> ProbePng(const std::filesystem::path& path);

}  // namespace owval::ci
