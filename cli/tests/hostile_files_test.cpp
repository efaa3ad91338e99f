// Hostile files and paths found by a sweep of every command (2026-11-30): each is one line naming
// the file, exit 2, and nothing written or replaced.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

void ExpectRefused(const Result& r, const std::string& says, const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << what << ": one line: " << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << what << ": " << r.err;
}

// The rename that commits an output replaced a symbolic link, not its target: `predict -o
// /dev/stdout > file` left /dev/stdout a regular file.
TEST(HostileFiles, AnOutputThatIsASymbolicLinkIsRefusedAndTheLinkKept) {
  const fs::path dir = Scratch();
  std::ofstream(dir / "target.json") << "{}\n";
  fs::create_symlink("target.json", dir / "link.json");
  ExpectRefused(Owval("predict one_sprig -o " + (dir / "link.json").string()),
                "link.json: is a symbolic link", "predict -o link");
  EXPECT_TRUE(fs::is_symlink(dir / "link.json"));
  EXPECT_EQ(Slurp(dir / "target.json"), "{}\n");
  ExpectRefused(Owval("compare " + kOneSprig + " " + kOneSprig + " --markdown " +
                      (dir / "link.json").string()),
                "is a symbolic link", "compare --markdown link");
  EXPECT_TRUE(fs::is_symlink(dir / "link.json"));
}

// The first `lines` lines of the bundled one_sprig run (11 header lines, then frame 0 lists
// every particle) written to `file`.
void FirstLines(const fs::path& file, std::size_t lines) {
  std::ifstream in(kBundledOneSprig);
  std::ofstream out(file);
  std::string line;
  for (std::size_t n = 0; n < lines && std::getline(in, line); ++n) out << line << "\n";
}

// One frame is no run: a reference of one frame passed every candidate, one frozen after its
// first frame included; inspect said "signal: the time window holds 1 samples" of no file.
TEST(HostileFiles, AOneFrameTrajectoryIsRefusedNamingTheFile) {
  const fs::path dir = Scratch();
  std::ifstream header(kBundledOneSprig);
  std::size_t counts[3] = {};
  std::string line;
  for (int n = 0; n < 9 && std::getline(header, line); ++n)
    if (n >= 6) counts[n - 6] = std::stoul(line);
  FirstLines(dir / "one.txt", 11 + counts[0] + counts[1] + counts[2]);
  ASSERT_EQ(
      Owval("convert " + (dir / "one.txt").string() + " " + (dir / "one.h5").string()).exit_code,
      0);
  for (const std::string name : {"one.txt", "one.h5"}) {
    const std::string file = (dir / name).string();
    ExpectRefused(Owval("compare " + file + " " + kOneSprig), name + ": holds 1 frame(s)",
                  "compare, a one-frame reference " + name);
    ExpectRefused(Owval("inspect " + file), name + ": holds 1 frame(s); expected at least 2",
                  "inspect " + name);
  }
  ASSERT_EQ(Owval("predict one_sprig -o " + (dir / "p.json").string()).exit_code, 0);
  ExpectRefused(Owval("reconcile " + (dir / "p.json").string() + " " + (dir / "one.h5").string()),
                "one.h5: holds 1 frame(s)", "reconcile");
  // As a candidate it is a run that stopped early: the window gate fails it.
  EXPECT_EQ(Owval("compare " + kOneSprig + " " + (dir / "one.h5").string()).exit_code, 1);
  // Another scene's run: the line names the candidate ("wrong particle count: ..." named none).
  ASSERT_EQ(Owval("run hanging_chain --time 0.001 -o " + (dir / "chain").string()).exit_code, 0);
  ExpectRefused(Owval("compare " + kOneSprig + " " + (dir / "chain/trajectory.h5").string()),
                "chain/trajectory.h5: ", "another scene");
  EXPECT_NE(Owval("compare " + kOneSprig + " " + (dir / "chain/trajectory.h5").string())
                .err.find(" particles; expected the reference's "),
            std::string::npos);
}

TEST(HostileFiles, WconIsRefusedAsATrajectoryToRead) {
  const fs::path dir = Scratch();
  std::ofstream(dir / "w.wcon") << "{}\n";
  ExpectRefused(Owval("convert " + (dir / "w.wcon").string() + " " + (dir / "x.h5").string()),
                "w.wcon: is WCON, which owval writes but does not read", "convert w.wcon");
  EXPECT_FALSE(fs::exists(dir / "x.h5"));
}

// A good candidate.h5 beside a failing candidate.txt: the checklist judged the .h5 and said
// ready; quick-test and validate took the .h5 too.
TEST(HostileFiles, APullRequestDirectoryWithTwoCandidatesIsRefused) {
  const fs::path dir = Scratch() / "pr";
  fs::create_directories(dir);
  ASSERT_EQ(Owval("convert " + kOneSprig + " " + (dir / "reference.h5").string()).exit_code, 0);
  fs::copy_file(dir / "reference.h5", dir / "candidate.h5");
  fs::copy_file(kBundledOneSprig, dir / "candidate.txt");
  const std::string says = "pr: holds both candidate.h5 and candidate.txt; expected one candidate";
  ExpectRefused(Owval("checklist " + dir.string() + " --reference " + kOneSprig), says,
                "checklist");
  ExpectRefused(Owval("ci quick-test " + dir.string()), says, "ci quick-test");
  ExpectRefused(Owval("ci validate " + dir.string() + " --reference " + kOneSprig), says,
                "ci validate");
}

// nlohmann keeps the last of a key given twice: a backends file's second "mine" replaced the
// first without a word. Names went to the terminal raw, escapes and newlines included.
TEST(HostileFiles, ABackendsFileWithATwiceGivenKeyOrAnUnprintableNameIsRefused) {
  const fs::path dir = Scratch();
  const std::string entry = R"({"command": "true {out}", "output": "{out}/p.txt"})";
  std::ofstream(dir / "twice.json")
      << R"({"backends": {"mine": )" << entry << R"(, "mine": )" << entry << "}}\n";
  ExpectRefused(Owval("backends list --backends " + (dir / "twice.json").string()),
                "twice.json: \"mine\" is given twice in one object", "a key given twice");
  std::ofstream(dir / "escape.json") << R"({"backends": {"a\u001b[2Jb": )" << entry << "}}\n";
  const Result escape = Owval("backends list --backends " + (dir / "escape.json").string());
  ExpectRefused(escape, "escape.json: backend \"a", "an escape in a name");
  EXPECT_EQ(escape.err.find('\x1b'), std::string::npos);
  EXPECT_EQ(escape.out, "");
}

}  // namespace
}  // namespace owval::testing
