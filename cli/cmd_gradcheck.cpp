// owval gradcheck [KERNEL...|all]: the XPBD substrate's backward kernels against central
// differences (engine/src/xpbd/gradcheck.cpp); -o writes fd_tests.json (checklist item 7).
#include "command.hpp"
#include "owval/base/format.hpp"
#include "owval/engine/gradient.hpp"
#include "owval/pipeline/gradcheck_request.hpp"

namespace owval::cli {
namespace {

struct GradCheckArgs {
  pipeline::GradCheckRequest request;
  bool json = false;
};

void SetUpGradcheck(CLI::App& app) {
  auto a = std::make_shared<GradCheckArgs>();
  pipeline::GradCheckRequest& r = a->request;
  r.shared_reference = SharedReference();
  CLI::App* cmd = app.add_subcommand(
      "gradcheck", "XPBD backward kernels against central differences in double (issue 14)");
  std::string kernels = "all";
  for (const std::string& name : engine::GradCheckKernels()) kernels += ", " + name;
  cmd->footer("Kernels: " + kernels +
              ". Each runs at eps = 1e-3 and its own eps; a test passes at relative error <= "
              "--tolerance. Exit 1 when any test fails.");
  cmd->add_option("kernels", r.options.kernels, "Kernels to check (default all)")
      ->check(GivenName());
  cmd->add_option("--directions", r.options.directions, "Random directions per kernel and eps")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--seed", r.options.seed, "Random seed");
  cmd->add_option("--tolerance", r.options.tolerance, "Relative error a kernel test must reach")
      ->check(Positive());
  cmd->add_option("--config", r.options.end_to_end_config,
                  "Configuration of the end-to-end (reverse) test (default: the shared demo1)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--reference", r.reference,
                  "End-to-end loss: elastic and liquid centroids against this run (default with "
                  "the default --config: the shared OpenCL demo1 run; without: the model's own "
                  "trajectory at shifted parameters)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--steps", r.options.end_to_end_steps, "Steps of the end-to-end test")
      ->check(CLI::Range(20, 100000));
  cmd->add_option("--density-passes", r.options.end_to_end_density_passes,
                  "Step scheme of the end-to-end test: xpbd_density_passes (default the run's: "
                  "1, the split step; 0: the unsplit step)")
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--alpha-density", r.options.end_to_end_alpha_density,
                  "Density compliance of the end-to-end test (s^2/cu^2, >= 0; 0 is a value, a "
                  "rigid constraint, as in bench gradient; default " +
                      FormatNumber(r.options.end_to_end_alpha_density) +
                      ": at the model's own value demo1's 100-step loss is chaotic, docs/xpbd.md)")
      ->check(NonNegative());
  cmd->add_option("-o,--out,--output", r.output, "Write fd_tests.json here")->check(OutputPath());
  AddJsonFlag(cmd, &a->json);
  cmd->callback([a] {
    PrintReport(RunGradCheckRequest(a->request), a->json, &pipeline::GradCheckResult::ToText);
  });
}

const bool gradcheck_registered = RegisterCommand(&SetUpGradcheck);

}  // namespace
}  // namespace owval::cli
