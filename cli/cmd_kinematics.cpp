// owval kinematics TRAJ_OR_WCON: the worm's speed, bend frequency, wavelength and amplitude.
#include <iostream>

#include "command.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/kinematics/worm_track.hpp"

namespace owval::cli {
namespace {

struct KinematicsArgs {
  std::string input;
  bool json = false;
};

void RunKinematics(const KinematicsArgs& a) {
  const kinematics::Report r = kinematics::AnalyseFile(a.input);
  if (a.json) {
    nlohmann::json j = r.ToJson();
    j["input"] = a.input;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << r.ToText();
  }
}

void SetUpKinematics(CLI::App& app) {
  auto a = std::make_shared<KinematicsArgs>();
  CLI::App* cmd = app.add_subcommand(
      "kinematics", "Worm kinematics (Yemini et al. 2013): speed, bend frequency, wavelength");
  AddInput(cmd, "input", &a->input, "Worm trajectory (any format) or WCON file (.wcon, .json)")
      ->check(CLI::ExistingFile);
  AddJsonFlag(cmd, &a->json, "the kinematics");
  cmd->callback([a] { RunKinematics(*a); });
}

const bool kinematics_registered = RegisterCommand(&SetUpKinematics);

}  // namespace
}  // namespace owval::cli
