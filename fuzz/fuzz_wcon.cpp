// Fuzz target: the WCON reader (trajectory/src/wcon_reader.cpp: json::sax_parse, its line
// counting, the spools and the checks of each time point), through ReadWcon, which reads every
// time point. The reader reads files, so each input is written to a scratch file first.
#include <filesystem>

#include "fuzz_common.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/worm_formats.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_wcon");
  static const std::filesystem::path path = scratch / "input.wcon";
  owval::fuzz::WriteInput(path, data, size);
  try {
    owval::ReadWcon(path);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
