// Fuzz target: a fit's history (fit/history.json, docs/fit_history.md) as `owval checklist` reads
// it for item 6: RunChecklist over a scratch directory holding the history and a small reference
// trajectory (so the targets' tracks and the gradient fit's loss record are read against it, as
// the pipeline's directories have them), with the caller's scenario targets and fitted backend
// set; and sgd::RerunBestIterate on the same JSON, which the checklist reaches only once the
// targets agree with the reference. No fit/configuration.txt is written, so no rerun simulates.
//
// Item 6's detail is a report line, not an exception, so CheckMessage does not apply to it; a
// raw library message in it (nlohmann's "[json.exception.type_error.302] type must be string")
// is the finding this target looks for, unless the input itself holds those words (a parse
// error quotes what it read): the detail must name the history's field instead.
#include <filesystem>
#include <string>
#include <string_view>

#include "fuzz_common.hpp"
#include "owval/base/json_file.hpp"
#include "owval/ci/checklist.hpp"
#include "owval/sgd/fit_record.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace {

namespace fs = std::filesystem;

// A two-frame OpenCL-layout trajectory (fuzz/corpus/text's opencl.txt, cut): particle 0 moves.
constexpr const char* kReference =
    "0\n20\n0\n20\n0\n20\n1\n1\n2\n2e-05\n20\n"
    "5\t5\t5\t2.1\n6\t5.5\t5\t1.1\n1\t1\t1\t3\n19\t1\t1\t3.1\n"
    "5.1\t4.95\t5\t2.1\n6.1\t5.45\t5\t1.1\n"
    "5.2\t4.9\t5\t2.1\n6.2\t5.4\t5\t1.1\n";

// nlohmann's exceptions say "[json.exception.type_error.302] type must be string, but is
// number"; the tag can reach a report only from the library, or echoed from the input itself.
void CheckNoLibraryMessage(const std::string& text, std::string_view input) {
  for (const char* tag : {"[json.exception.", "type must be ", "cannot use value()"})
    if (text.find(tag) != std::string::npos && input.find(tag) == std::string_view::npos)
      __builtin_trap();
}

owval::ci::ChecklistOptions CallerOptions() {
  owval::ci::ChecklistOptions o;
  o.scenario_fit_targets = nlohmann::json::parse(
      R"([{"metric": "period", "weight": 1}, {"metric": "half_amplitude", "weight": 0.25}])");
  owval::backends::Backend store;  // a reviewer's entry that runs nothing
  store.name = "port";
  store.kind = owval::backends::BackendKind::kStore;
  store.store = "/nonexistent/owval-fuzz-store";
  store.defined_in = "fuzz_history";
  o.fit_backend = store;
  return o;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_history");
  static const fs::path dir = scratch.path();
  static const bool made = [] {
    fs::create_directories(dir / "fit");
    owval::fuzz::WriteInput(dir / "reference.txt", kReference);
    return true;
  }();
  (void)made;
  static const owval::ci::ChecklistOptions options = CallerOptions();
  const fs::path history = dir / "fit" / "history.json";
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  owval::fuzz::WriteInput(history, input);
  try {
    const owval::ci::ChecklistReport report = owval::ci::RunChecklist(dir, options);
    for (const owval::ci::ChecklistItem& item : report.items)
      if (item.number == 6) CheckNoLibraryMessage(item.detail, input);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  nlohmann::json parsed;
  try {
    parsed = owval::ReadJsonFile(history);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
    return 0;
  }
  owval::sgd::FitRerunOptions rerun;
  rerun.backend = &*options.fit_backend;
  CheckNoLibraryMessage(owval::sgd::RerunBestIterate(parsed, dir / "fit", rerun).not_verified,
                        input);
  return 0;
}
