// OmeZarrReader's .zarray checks (zarr_reader.cpp): a field of another JSON type than zarr v2's
// is refused by one line naming the file and the field, never nlohmann's own exception (found by
// fuzz/fuzz_zarr.cpp: a .zarray that was an array, a "zarr_format" string, "shape": [1e300] and
// a compressor that was a string escaped as json::type_error, not InputError).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;

void WriteFile(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << bytes;
}

std::string Meta(const std::string& shape, const std::string& chunks, const char* dtype) {
  return R"({"zarr_format": 2, "shape": )" + shape + R"(, "chunks": )" + chunks +
         R"(, "dtype": ")" + dtype +
         R"(", "compressor": null, "fill_value": 0, "order": "C", "filters": null})";
}

// One frame of one particle at (1, 2, 3) µm, type 2.1, at t = 0.5 s, uncompressed.
fs::path SmallStore(const std::string& name) {
  const fs::path store = testing::TestScratch(name);
  const float position[3] = {1, 2, 3}, type = 2.1f;
  const double time = 0.5;
  WriteFile(store / "body/positions/.zarray", Meta("[1, 1, 3]", "[1, 1, 3]", "<f4"));
  WriteFile(store / "body/positions/0.0.0",
            std::string(reinterpret_cast<const char*>(position), sizeof position));
  WriteFile(store / "body/types/.zarray", Meta("[1]", "[1]", "<f4"));
  WriteFile(store / "body/types/0", std::string(reinterpret_cast<const char*>(&type), 4));
  WriteFile(store / "body/time/.zarray", Meta("[1]", "[1]", "<f8"));
  WriteFile(store / "body/time/0", std::string(reinterpret_cast<const char*>(&time), 8));
  return store;
}

std::string Refusal(const fs::path& store) {
  try {
    OmeZarrReader reader(store);
    reader.FrameMicrometres(0);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ZarrReader, ReadsASmallStore) {
  const fs::path store = SmallStore("small");
  OmeZarrReader reader(store);
  ASSERT_EQ(reader.frame_count(), 1u);
  ASSERT_EQ(reader.particle_count(), 1u);
  EXPECT_EQ(reader.time_s()[0], 0.5);
  EXPECT_EQ(reader.FrameMicrometres(0)[2], 3.0f);
}

// Whole numbers written as floats are dimensions too (1e15 is then refused by the memory budget,
// OmeZarr.OwvalsReaderHoldsAClaimedChunkToTheMemoryBudget).
TEST(ZarrReader, WholeFloatsAreDimensions) {
  const fs::path store = SmallStore("floats");
  WriteFile(store / "body/positions/.zarray", Meta("[1.0, 1e0, 3]", "[1, 1, 3.0]", "<f4"));
  OmeZarrReader reader(store);
  EXPECT_EQ(reader.FrameMicrometres(0)[1], 2.0f);
}

TEST(ZarrReader, AFieldOfAnotherTypeIsRefusedNamingTheField) {
  const struct {
    const char* zarray;
    const char* expected;
  } cases[] = {
      {R"([2, 1, 3])", ".zarray: expected a JSON object"},
      {R"({"zarr_format": "2"})", ".zarray: zarr_format: expected 2"},
      {R"({"zarr_format": 2, "dtype": 4})", R"(.zarray: dtype: expected "<f4")"},
      {R"({"zarr_format": 2, "dtype": "<f4", "order": "C", "shape": [1e300, 1, 3],
          "chunks": [1, 1, 3]})",
       ".zarray: shape: expected 3 whole numbers (dimensions)"},
      {R"({"zarr_format": 2, "dtype": "<f4", "order": "C", "shape": [1, 1, 3],
          "chunks": [1, -1, 3]})",
       ".zarray: chunks: expected 3 whole numbers (dimensions)"},
      {R"({"zarr_format": 2, "dtype": "<f4", "order": "C", "shape": [1, 1, 3],
          "chunks": [1.5, 1, 3]})",
       ".zarray: chunks: expected 3 whole numbers (dimensions)"},
      {R"({"zarr_format": 2, "dtype": "<f4", "order": "C", "shape": [1, 1, 3],
          "chunks": [1, 1, 3], "compressor": "zlib"})",
       R"(.zarray: compressor: expected {"id": "zlib"} or null)"},
      {R"({"zarr_format": 2, "dtype": "<f4", "order": "C", "shape": [1, 1, 3],
          "chunks": [1, 1, 3], "fill_value": 1e300})",
       ".zarray: fill_value: expected a number within float32's range"},
      {R"({"zarr_format": 2,)", ".zarray:1: not valid JSON: parse error"},
  };
  for (const auto& c : cases) {
    const fs::path store = SmallStore("fields");
    WriteFile(store / "body/positions/.zarray", c.zarray);
    const std::string refusal = Refusal(store);
    EXPECT_EQ(refusal.rfind((store / "body/positions").string() + "/" + c.expected, 0), 0u)
        << c.zarray << " -> " << refusal;
  }
}

}  // namespace
}  // namespace owval
