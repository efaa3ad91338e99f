// Fuzz target: the HDF5 trajectory reader (owval's pre-flight checks, its parallel chunk path and
// libhdf5's fallback). HDF5 reads files, so each input is written to a scratch file first.
#include <unistd.h>

#include <filesystem>

#include "fuzz_common.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  owval::fuzz::SetUpOnce();
  // Removed when the program exits (a crash keeps it, and the input that crashed is saved).
  static const owval::testing::ScratchDirectory scratch("fuzz_hdf5");
  static const std::filesystem::path path = scratch / "input.h5";
  owval::fuzz::WriteInput(path, data, size);
  try {
    owval::ReadHdf5(path);
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
