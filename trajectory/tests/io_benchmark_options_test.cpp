// `owval bench io`'s HDF5 options are checked before its text file is generated.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/io_benchmark.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;

void ExpectRefusedBeforeWork(const IoBenchmarkOptions& o, const std::string& says) {
  fs::remove_all(o.directory);
  try {
    RunIoBenchmark(o);
    FAIL() << "accepted; expected: " << says;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(says, 0), 0u) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.directory)) << "generated files before refusing: " << says;
}

TEST(IoBenchmarkOptions, RefusesADeflateLevelOrChunkLibhdf5WouldNot) {
  IoBenchmarkOptions o;
  o.text_size_mb = 1;
  o.quiet = true;
  o.directory = owval::testing::TestScratch() / "bench";
  o.hdf5.compression_level = 99;
  ExpectRefusedBeforeWork(o, "--hdf5-level: expected a deflate level 0..9, found 99");
  o.hdf5.compression_level = -1;
  ExpectRefusedBeforeWork(o, "--hdf5-level: expected a deflate level 0..9, found -1");
  o.hdf5.compression_level = 4;
  o.hdf5.frames_per_chunk = 0;
  ExpectRefusedBeforeWork(o, "--hdf5-chunk-frames: expected 1 or more frames a chunk, found 0");
}

}  // namespace
}  // namespace owval
