// Fuzz target: Sibernetic's side logs, plain or gzip-compressed (kinematics/src/log_lines.cpp's
// line reading): the midline log worm_motion_log.txt (each line's t, X:, Y:, Z: blocks of 99 bin
// means) through ReadWormMotionLog as `owval kinematics` and the checklist's side-file gate read
// it, then the same bytes as muscles_activity_buffer.txt (96 finite values a line) through
// MuscleLogReader as the muscle log's side-file gate reads it. The readers read files, so each
// input is written to a scratch file first.
#include <filesystem>

#include "fuzz_common.hpp"
#include "owval/kinematics/muscle_log.hpp"
#include "owval/kinematics/side_files.hpp"
#include "owval/testing/scratch_directory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_side_files");
  static const std::filesystem::path path = scratch / "side_file.txt";
  owval::fuzz::WriteInput(path, data, size);
  try {
    owval::kinematics::ReadWormMotionLog(path);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  try {
    owval::kinematics::MuscleLogReader muscles(path);
    owval::kinematics::PrintedActivations values{};
    while (muscles.Next(&values)) {
    }
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
