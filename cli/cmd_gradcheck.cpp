// owval gradcheck [KERNEL...|all]: the XPBD substrate's backward kernels against central
// differences (engine/src/xpbd/gradcheck.cpp); -o writes fd_tests.json (checklist item 7).
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/engine/gradient.hpp"
#include "owval/sgd/gradcheck.hpp"
#include "owval/sgd/gradient_fit.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::cli {
namespace {

struct GradCheckArgs {
  engine::GradCheckOptions options;
  std::string reference, output;
  bool json = false;
};

void RunGradCheckCommand(GradCheckArgs& a) {
  if (!a.output.empty()) {
    CheckOutputPath(a.output);
    CheckOutputIsNotAnInput(a.output, {a.options.end_to_end_config, a.reference});
  }
  const std::filesystem::path demo1 = std::filesystem::path(OWVAL_SHARED_DIR) / "reference/demo1";
  if (a.options.end_to_end_config.empty()) {
    a.options.end_to_end_config = (demo1 / "configuration").string();
    if (a.reference.empty()) a.reference = (demo1 / "position_buffer.txt").string();
  }
  if (!a.reference.empty()) {  // demo1's fit loss: the centroids against a reference run
    const Trajectory reference = ReadTrajectory(a.reference, {.quiet = true});
    a.options.end_to_end_loss =
        sgd::GroupCentroidLoss(reference, {"elastic", "liquid"}, a.options.end_to_end_steps, 1.0);
    a.options.end_to_end_loss_name = "centroids vs " + a.reference;
  }
  const engine::GradCheckSummary summary = engine::RunGradCheck(a.options);
  const nlohmann::json j = sgd::GradCheckJson(summary, a.options);
  if (!a.output.empty()) WriteFileAtomically(a.output, j.dump(2) + "\n");
  if (a.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    for (const engine::GradCheckTest& t : summary.tests)
      std::cout << (t.pass ? "pass " : "FAIL ") << t.name << ": fd " << t.finite_difference
                << ", analytic " << t.analytic << ", relative error " << t.relative_error << "\n";
    std::cout << summary.BriefReport() << "\n";
  }
  SetExitCode(summary.pass ? 0 : 1);
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<GradCheckArgs>();
  CLI::App* cmd = app.add_subcommand(
      "gradcheck", "XPBD backward kernels against central differences in double (issue 14)");
  cmd->footer(
      "Kernels: all, sph_density, forces, predict, density_projection, bond_projection, "
      "bond_projection_jacobi, box, velocity, velocity_correction, step, reverse. Each runs at eps "
      "= 1e-3 and its own eps; a test "
      "passes at relative error <= --tolerance. Exit 1 when any test fails.");
  cmd->add_option("kernels", a->options.kernels, "Kernels to check (default all)");
  cmd->add_option("--directions", a->options.directions, "Random directions per kernel and eps")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--seed", a->options.seed, "Random seed");
  cmd->add_option("--tolerance", a->options.tolerance, "Relative error a kernel test must reach")
      ->check(Positive());
  cmd->add_option("--config", a->options.end_to_end_config,
                  "Configuration of the end-to-end (reverse) test (default: the shared demo1)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--reference", a->reference,
                  "End-to-end loss: elastic and liquid centroids against this run (default with "
                  "the default --config: the shared OpenCL demo1 run; without: the model's own "
                  "trajectory at shifted parameters)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--steps", a->options.end_to_end_steps, "Steps of the end-to-end test")
      ->check(CLI::Range(20, 100000));
  cmd->add_option("--density-passes", a->options.end_to_end_density_passes,
                  "Step scheme of the end-to-end test: xpbd_density_passes (default the run's: "
                  "1, the split step; 0: the unsplit step)")
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--alpha-density", a->options.end_to_end_alpha_density,
                  "Density compliance of the end-to-end test (s^2/cu^2, >= 0; 0 is a value, a "
                  "rigid constraint, as in bench gradient; default 4e-8: at the model's own "
                  "value demo1's 100-step loss is chaotic, docs/xpbd.md)")
      ->check(NonNegative());
  cmd->add_option("-o,--out,--output", a->output, "Write fd_tests.json here");
  cmd->add_flag("--json", a->json, "Machine-readable output on stdout");
  cmd->callback([a] { RunGradCheckCommand(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
