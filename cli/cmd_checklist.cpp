// owval checklist DIR: the PR checklist bot (Markdown comment, exit 1 when not ready).
#include <iostream>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/ci/checklist.hpp"

namespace owval::cli {
namespace {

struct ChecklistArgs {
  std::string directory;
  std::string markdown;
  bool json = false;
};

void RunChecklistCommand(const ChecklistArgs& a) {
  const ci::ChecklistReport report = ci::RunChecklist(a.directory);
  if (!a.markdown.empty()) WriteFileAtomically(a.markdown, report.ToMarkdown());
  std::cout << (a.json ? report.ToJson().dump(2) + "\n" : report.ToMarkdown());
  SetExitCode(report.exit_code());
}

void SetUp(CLI::App& app) {
  auto args = std::make_shared<ChecklistArgs>();
  CLI::App* cmd = app.add_subcommand(
      "checklist", "Phase 8: the 10-item PR checklist over an artifact directory");
  cmd->add_option("directory", args->directory, "PR artifact directory (see docs/checklist.md)")
      ->required();
  cmd->add_option("--markdown", args->markdown, "Also write the Markdown comment to this file");
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args] { RunChecklistCommand(*args); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
