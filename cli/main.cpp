// owval: one CLI over the owval libraries. Every subcommand lives in its own cmd_*.cpp.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <vector>

#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/progress.hpp"

namespace owval::cli {
namespace {
std::vector<CommandSetUp>& Registry() {
  static std::vector<CommandSetUp> registry;
  return registry;
}
int g_exit_code = 0;
GlobalFlags g_flags;
}  // namespace

bool RegisterCommand(CommandSetUp set_up) {
  Registry().push_back(std::move(set_up));
  return true;
}
CLI::App& Bench(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands([](CLI::App* a) { return a->get_name() == "bench"; }))
    return *sub;
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks (JSON results)");
  bench->require_subcommand(1);
  return *bench;
}

void SetExitCode(int code) { g_exit_code = code; }
const GlobalFlags& Flags() { return g_flags; }

std::filesystem::path DataDir() {
  if (const char* dir = std::getenv("OWVAL_DATA_DIR")) return dir;
  return OWVAL_SOURCE_DIR;
}

}  // namespace owval::cli

int main(int argc, char** argv) {
  using namespace owval::cli;
  CLI::App app{"owval: validation and benchmark harness for Sibernetic-style particle physics"};
  app.set_version_flag("--version", OWVAL_VERSION);
  app.add_flag("-q,--quiet", g_flags.quiet, "No progress lines on stderr");
  app.require_subcommand(1);
  app.fallthrough();
  app.parse_complete_callback([] { owval::SetQuietMode(g_flags.quiet); });
  for (const auto& set_up : Registry()) set_up(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : owval::kExitBadInput;
  } catch (const owval::InputError& e) {
    std::fprintf(stderr, "owval: error: %s\n", e.what());
    return owval::kExitBadInput;
  } catch (const owval::SimulationError& e) {
    std::fprintf(stderr, "owval: error: %s\n", e.what());
    return owval::kExitGateFailed;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "owval: error: %s\n", e.what());
    return owval::kExitBadInput;
  }
  return g_exit_code;
}
