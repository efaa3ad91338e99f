#pragma once
// How a command group plugs into the owval executable: a cmd_*.cpp file defines
//   static const bool registered = owval::cli::RegisterCommand(&SetUpMyCommand);
// where SetUpMyCommand adds a subcommand to the app and sets its callback. Callbacks report bad
// input by throwing owval::InputError (exit 2) and gate failures through SetExitCode(1).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "owval/trajectory/track.hpp"

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

// The tracked quantity as given on the command line (--PREFIXparticle, --PREFIXgroup,
// --PREFIXaxis): only what was given, laid over a command's default track (a manifest's, or
// particle 0 y) by Over.
struct TrackFlags {
  std::optional<std::size_t> particle;
  std::string group;                // elastic | liquid | all (excludes the particle)
  std::optional<std::string> axis;  // x | y | z
  bool given() const { return particle || !group.empty(); }
  Track Over(Track base) const;
};
// Adds the three flags; `subject` says what the track is for ("Tracked", "Print this").
void AddTrackFlags(CLI::App* cmd, TrackFlags* flags, const std::string& prefix,
                   const std::string& subject);

// The exit code the process ends with once the callback returns (default 0).
void SetExitCode(int code);

// Global flags, read by every command.
struct GlobalFlags {
  bool quiet = false;
};
const GlobalFlags& Flags();

// Where owval finds built-in data: the source tree's scenarios/ and reference_trajectories/.
// Overridable with the OWVAL_DATA_DIR environment variable (a copy of the source tree's root).
std::filesystem::path DataDir();

}  // namespace owval::cli
