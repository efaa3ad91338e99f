// Issue 18: a full disk during `render` and `convert`. RLIMIT_FSIZE stands in for the full disk
// (with SIGXFSZ ignored, a write past the limit fails with EFBIG, as ENOSPC would): exit 2 with
// one line naming the output, no file under the final name, no temporary left beside it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_support.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

// `owval --quiet ARGS` with files limited to `kib` KiB.
Result OwvalOnAFullDisk(const std::string& args, int kib) {
  return RunCaptured("bash -c 'trap \"\" XFSZ; ulimit -f " + std::to_string(kib) + "; exec " +
                     std::string(OWVAL_EXE) + " --quiet " + args + "'");
}

// Files in `dir` other than the ones the test put there.
std::size_t Leftovers(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    n += e.path().filename() != "stdout.txt" && e.path().filename() != "stderr.txt";
  return n;
}

TEST(FullDisk, RenderIsExit2WithNoVideoAndNoTemporary) {
  const fs::path dir = Scratch() / "full_render";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Result r = OwvalOnAFullDisk(
      "render " + kOneSprig + " -o " + (dir / "v.mp4").string() + " --size 640x360 --max-frames 60",
      24);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("v.mp4"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  EXPECT_EQ(Leftovers(dir), 0u);
}

TEST(FullDisk, ConvertIsExit2WithNoOutputAndNoTemporary) {
  const fs::path dir = Scratch() / "full_convert";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* name : {"t.h5", "t.txt"}) {
    const Result r = OwvalOnAFullDisk(
        "convert " + kOneSprig + " " + (dir / name).string() + " --out-layout native", 24);
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_EQ(Leftovers(dir), 0u) << name;
  }
}

// A streamed run: the text and HDF5 writers both fail on the full disk. Nothing under a final
// name; the run says which output it could not write.
TEST(FullDisk, RunIsExit2WithNoOutputUnderItsFinalName) {
  const fs::path dir = Scratch() / "full_run";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Result r = OwvalOnAFullDisk(
      "run one_sprig --time 0.02 --log-step 1 --out " + (dir / "out").string(), 24);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "position_buffer.txt"));
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.h5"));
  std::size_t temporaries = 0;
  if (fs::exists(dir / "out"))
    for (const auto& e : fs::directory_iterator(dir / "out"))
      temporaries += e.path().filename().string().find(".tmp.") != std::string::npos;
  EXPECT_EQ(temporaries, 0u);
}

}  // namespace
}  // namespace owval::testing
