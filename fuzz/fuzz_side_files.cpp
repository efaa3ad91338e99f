// Fuzz target: Sibernetic's midline log, worm_motion_log.txt[.gz] (kinematics/src/side_files.cpp:
// gzopen's line reading, plain or gzip-compressed, and each line's t, X:, Y:, Z: blocks of 99 bin
// means), through ReadWormMotionLog as `owval kinematics` and the checklist's side-file gate read
// it. The reader reads files, so each input is written to a scratch file first.
#include <filesystem>

#include "fuzz_common.hpp"
#include "owval/kinematics/side_files.hpp"
#include "owval/testing/scratch_directory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_side_files");
  static const std::filesystem::path path = scratch / "worm_motion_log.txt";
  owval::fuzz::WriteInput(path, data, size);
  try {
    owval::kinematics::ReadWormMotionLog(path);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
