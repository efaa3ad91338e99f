#pragma once
// Sibernetic's own demos as scenarios, read from a user's checkout of openworm/sibernetic: those
// configurations are not ours to copy, so owval carries only a manifest per demo
// (scenarios/sibernetic/NAME.json) naming the file by its path inside the checkout, the run's
// time, time step and log step (those of the runs in ../shared/reference), and its track and
// gates:
//   {"name": "demo1", "sibernetic": {"configuration": "configuration/demo1", "time_s": 0.2,
//    "time_step_s": 2e-05, "log_step": 20}, "track": {...}, "gates": {...}}
// `owval compare A B --sibernetic DIR` (or $SIBERNETIC_HOME) runs the suite over them.
#include <filesystem>
#include <string>
#include <vector>

#include "owval/backends/scenario_store.hpp"

namespace owval::backends {

// The checkout to use: `flag` when given, else $SIBERNETIC_HOME, else "" (none).
std::filesystem::path SiberneticCheckout(const std::string& flag);

// The named demos (all of `manifests` when `names` is empty: those whose configuration the
// checkout has) as scenarios whose configuration lies in `checkout`. InputError naming the file
// for a malformed manifest, an unknown name, or a named demo the checkout lacks.
std::vector<Scenario> SiberneticScenarios(const std::filesystem::path& checkout,
                                          const std::filesystem::path& manifests,
                                          const std::vector<std::string>& names);

// The manifest in `manifests` (sorted by name, the first) whose sibernetic.configuration is
// `repository_path`, or "" when none is: how a store's run of a demo under another folder name
// (demo1_1s, whose meta.json names configuration/demo1) finds its track and gates.
std::filesystem::path SiberneticManifestOf(const std::filesystem::path& manifests,
                                           const std::string& repository_path);

}  // namespace owval::backends
