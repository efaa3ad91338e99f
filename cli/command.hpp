#pragma once
// How a command group plugs into the owval executable: a cmd_*.cpp file defines
//   const bool my_command_registered = owval::cli::RegisterCommand(&SetUpMyCommand);
// where SetUpMyCommand adds a subcommand to the app, binds its flags to the library's options and
// sets its callback. Callbacks report bad input by throwing owval::InputError (exit 2) and gate
// failures through SetExitCode(1). Both names are the command's own: the build compiles several
// command files as one (owval_wiring_code in CMakeLists.txt: unity batches).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/base/progress.hpp"
#include "owval/trajectory/track_choice.hpp"

namespace owval::cli {

using CommandSetUp = std::function<void(CLI::App& app)>;
bool RegisterCommand(CommandSetUp set_up);

// The shared "owval bench" group: each library adds its own benchmark as a subcommand of it,
// e.g. Bench(app).add_subcommand("engine", ...). Benchmarks write JSON.
CLI::App& Bench(CLI::App& app);

// A particle index: digits only, at most 18 of them ("--particle -1" is refused, not wrapped).
const CLI::Validator& ParticleIndex();
// A finite number > 0 and a finite number >= 0 (a NaN or infinite threshold would pass every
// frame). Their messages say what was expected and what was found ("expected a number > 0,
// found '0'"); CLI11's own print the bounds as 300-digit doubles.
const CLI::Validator& Positive();
const CLI::Validator& NonNegative();
const CLI::Validator& Fraction();  // 0 to 1 (NaN refused, which CLI::Range lets through)
// A count for an unsigned option: digits only ("-1" is refused, not wrapped).
const CLI::Validator& Count();
// Every option naming an output (-o/--out, --markdown, --json-out, ...): a path, not empty.
const CLI::Validator& OutputPath();
// Every option naming an input (--backends, --manifest, --reference, --scenario, ...): not empty.
const CLI::Validator& GivenName();
// A count that must be 1 or more (bench --steps, --frames), digits only.
const CLI::Validator& PositiveCount();

// A positional argument naming an input (a trajectory, a configuration, a directory): required,
// not empty. Further checks (CLI::ExistingFile) chain on the result.
template <class T>
CLI::Option* AddInput(CLI::App* cmd, const std::string& name, T* value,
                      const std::string& help = "") {
  return cmd->add_option(name, *value, help)->check(GivenName())->required();
}
// -o,--out: what the command writes (`help` says what), an output path.
template <class T>
CLI::Option* AddOut(CLI::App* cmd, T* out, const std::string& help) {
  return cmd->add_option("-o,--out", *out, help)->check(OutputPath());
}
// --markdown: also write `what` as Markdown to this file.
template <class T>
CLI::Option* AddMarkdownOut(CLI::App* cmd, T* markdown, const std::string& what) {
  return cmd->add_option("--markdown", *markdown, "Also write " + what + " as Markdown here")
      ->check(OutputPath());
}
// --layout: the Sibernetic text layout of the input; auto detects it.
inline void AddLayoutFlag(CLI::App* cmd, std::string* layout) {
  cmd->add_option("--layout", *layout, "Input text layout: auto, opencl or native")
      ->check(CLI::IsMember({"auto", "opencl", "native"}));
}
// --json: the command's result (`what`) printed as JSON on stdout instead of text.
inline void AddJsonFlag(CLI::App* cmd, bool* json, const std::string& what = "the report") {
  cmd->add_flag("--json", *json, "Print " + what + " as JSON (machine-readable) instead of text");
}

// The tracked quantity as given on the command line (--PREFIXparticle, --PREFIXgroup,
// --PREFIXaxis); `subject` says what the track is for ("Tracked", "Print this").
using TrackFlags = TrackChoice;
void AddTrackFlags(CLI::App* cmd, TrackChoice* flags, const std::string& prefix,
                   const std::string& subject);

// The exit code the process ends with once the callback returns (default 0).
void SetExitCode(int code);

// What most commands end with: the report as JSON (--json) or as `text` on stdout, and exit
// code 1 when it did not pass.
template <class Report>
void PrintReport(const Report& report, bool json, std::string (Report::*text)() const) {
  std::cout << (json ? report.ToJson().dump(2) + "\n" : (report.*text)());
  if (!report.pass()) SetExitCode(kExitGateFailed);
}

// Where owval finds built-in data: the source tree's scenarios/ and reference_trajectories/.
// Overridable with the OWVAL_DATA_DIR environment variable (a copy of the source tree's root).
std::filesystem::path DataDir();
// Sibernetic's reference runs (../shared/reference, or cmake's OWVAL_SHARED_DIR).
inline std::filesystem::path SharedReference() {
  return std::filesystem::path(OWVAL_SHARED_DIR) / "reference";
}

}  // namespace owval::cli
