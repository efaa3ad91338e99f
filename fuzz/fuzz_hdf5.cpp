// Fuzz target: the HDF5 trajectory readers (owval's pre-flight checks, its parallel chunk path and
// libhdf5's fallback; for a file ReadHdf5 takes, the streaming reader's row path too). HDF5 reads
// files, so each input is written to a scratch file first.
#include <unistd.h>

#include <filesystem>
#include <vector>

#include "fuzz_common.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/writer.hpp"

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
    return 0;
  }
  // Only then, as it costs a second contained dry run: frame by frame (DeflatedChunkRows).
  try {
    owval::Hdf5FrameReader stream(path);
    std::vector<float> positions(stream.header().type.size() * 3);
    for (std::size_t f = 0; f < stream.frame_count(); ++f) stream.ReadFrame(f, positions.data());
  } catch (const owval::InputError& e) {
    owval::fuzz::CheckMessage(e);
  }
  return 0;
}
