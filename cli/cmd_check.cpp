// owval check stability|incompressibility TRAJ: physical sanity gates (exit 1 on violation).
#include "command.hpp"
#include "owval/base/format.hpp"
#include "owval/compare/stability.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct CheckArgs {
  std::string path;
  bool json = false;
  compare::StabilityOptions stability;
  compare::IncompressibilityOptions incompressibility;
};

void RunCheckStability(const CheckArgs& a) {
  const auto frames = OpenTrajectoryArgument(a.path);  // frame by frame
  PrintReport(compare::CheckStability(*frames, a.stability), a.json,
              &compare::StabilityReport::ToTable);
}

void RunIncompressibility(const CheckArgs& a) {
  const auto frames = OpenTrajectoryArgument(a.path);  // frame by frame
  compare::IncompressibilityReport r;
  try {
    r = compare::CheckIncompressibility(*frames, a.incompressibility);
  } catch (const InputError& e) {
    throw InputError(a.path, 0, e.what());
  }
  PrintReport(r, a.json, &compare::IncompressibilityReport::ToTable);
}

void SetUpCheck(CLI::App& app) {
  CLI::App* check = app.add_subcommand("check", "Physical sanity gates on one trajectory");
  check->require_subcommand(1);
  auto args = std::make_shared<CheckArgs>();
  CLI::App* stability =
      check->add_subcommand("stability", compare::DescribeStability(args->stability));
  AddInput(stability, "trajectory", &args->path);
  stability
      ->add_option("--box-tolerance", args->stability.box_tolerance_cu,
                   "cu outside the box allowed")
      ->check(NonNegative());
  stability
      ->add_option("--speed-limit", args->stability.speed_limit_m_s,
                   "Mean speed (m/s) counted as blow-up")
      ->check(Positive());
  stability->add_option("--density-range", args->stability.density_max, "Maximum density (kg/m^3)")
      ->check(Positive());
  AddJsonFlag(stability, &args->json);
  stability->callback([args] { RunCheckStability(*args); });
  CLI::App* incompressible =
      check->add_subcommand("incompressibility", "Mean and max |rho/rho0 - 1| of liquid");
  AddInput(incompressible, "trajectory", &args->path);
  incompressible
      ->add_option("--rest-density", args->incompressibility.rest_density, "rho0 (kg/m^3)")
      ->check(Positive());
  incompressible
      ->add_option(
          "--limit", args->incompressibility.limit,
          "Allowed deviation (default " + FormatNumber(args->incompressibility.limit) + ")")
      ->check(Positive());
  AddJsonFlag(incompressible, &args->json);
  incompressible->callback([args] { RunIncompressibility(*args); });
}

const bool check_registered = RegisterCommand(&SetUpCheck);

}  // namespace
}  // namespace owval::cli
