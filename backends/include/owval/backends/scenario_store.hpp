#pragma once
// Scenarios of a store laid out like ../shared/reference: one folder per scenario with the
// configuration that was run ("configuration"), meta.json (time_step_s, log_step, and the time
// as timelimit_s, "timelimit=" in its command, or frames x log_step x time_step_s) and the
// recorded trajectory (position_buffer.txt, .txt.gz or trajectory.h5). meta.json's
// "configuration" is either a description (a string) or an object whose "repo_path" names the
// repository file that was run.
#include <filesystem>
#include <string>
#include <vector>

namespace owval::backends {

struct Scenario {
  std::string name;
  std::filesystem::path directory;
  std::filesystem::path configuration;  // "" when the folder has none
  double time_s = 0;
  double time_step_s = 2e-5;
  int log_step = 1;
  double recorded_wall_s = 0;  // meta.json's wall_s: the recorded run's wall time (0: not given)
  std::string recorded_wall_includes;  // what that wall time covers
  // The configuration's path inside Sibernetic's repository ("configuration/demo1"): meta.json's
  // configuration.repo_path, or a Sibernetic manifest's sibernetic.configuration ("": unknown).
  // A run of a demo under another folder name (demo1_1s) is still judged as that demo.
  std::string sibernetic_configuration;
};

// Reads directory/meta.json. InputError naming the file and field when it cannot.
Scenario ReadScenario(const std::filesystem::path& directory);

// The named scenarios of `root`, or, with no names, every folder that has a configuration and a
// meta.json (sorted by name). InputError for a name that is not a scenario folder of `root`.
std::vector<Scenario> FindScenarios(const std::filesystem::path& root,
                                    const std::vector<std::string>& names);

// The recorded trajectory of a scenario folder, or "" when it has none.
std::filesystem::path RecordedTrajectory(const std::filesystem::path& directory);

}  // namespace owval::backends
