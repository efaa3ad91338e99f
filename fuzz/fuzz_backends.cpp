// Fuzz target: the backends file (backends/src/registry.cpp, docs/backends.md) as `owval backends
// list [--json]` and `owval backends show NAME` read it: LoadRegistry on the file, then the
// registry's text and JSON listings and each backend's entry found by name. The reader reads a
// file, so each input is written to a scratch file first; "~/" paths resolve against a home
// that does not exist (nothing outside the scratch directory is read).
#include <filesystem>

#include "fuzz_common.hpp"
#include "owval/backends/registry.hpp"
#include "owval/testing/scratch_directory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_backends");
  static const std::filesystem::path path = scratch / "owval-backends.json";
  owval::fuzz::WriteInput(path, data, size);
  owval::backends::RegistryOptions options;
  options.file = path;
  options.current_directory = scratch.path();
  options.home = (scratch / "no-home").string();
  try {
    const owval::backends::Registry registry = owval::backends::LoadRegistry(options);
    (void)registry.ToText();
    (void)registry.ToJson().dump(2);
    for (const std::string& name : registry.Names()) (void)registry.Find(name).ToJson().dump(2);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
