// Fuzz target: a scenario manifest (JSON) through scenarios::LoadScenario, as `owval run NAME`
// reads scenarios/manifests/NAME.json.
#include <unistd.h>

#include <filesystem>

#include "fuzz_common.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/testing/scratch_directory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  namespace fs = std::filesystem;
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_manifest");
  static const fs::path dir = scratch.path();
  static const bool made = fs::create_directories(dir / "scenarios" / "manifests") || true;
  (void)made;
  owval::fuzz::WriteInput(dir / "scenarios" / "manifests" / "fuzz.json", data, size);
  try {
    owval::scenarios::LoadScenario("fuzz", dir);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
