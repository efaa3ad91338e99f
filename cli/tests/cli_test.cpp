// End-to-end behaviour of the owval executable: what a user meets on the command line.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "cli_support.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

TEST(Cli, InspectJsonReportsTheOneSprigPeriod) {
  const Result r = Owval("inspect " + kOneSprig + " --particle 0 --axis y --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["metrics"]["zero_crossing_period_s"].get<double>(), 0.7246e-3, 0.7246e-6);
  EXPECT_NE(j["layout"].get<std::string>().find("opencl"), std::string::npos);
}

// `--from nan` (or a negative time) was read as "no bound": exit 0 over the whole window.
TEST(Cli, InspectRefusesANonFiniteOrNegativeWindowBound) {
  for (const char* flag : {"--from", "--to"})
    for (const char* value : {"nan", "inf", "-1"}) {
      const Result r = Owval("inspect " + kOneSprig + " " + flag + " " + value);
      EXPECT_EQ(r.exit_code, 2) << flag << " " << value;
      EXPECT_EQ(r.err, "owval: usage: " + std::string(flag) + ": expected a number >= 0, found '" +
                           value + "' (see --help)\n");
    }
  EXPECT_EQ(Owval("inspect " + kOneSprig + " --from 0 --to 0.001").exit_code, 0);
}

// A resumed run takes its checkpoint's own arguments: `run --resume DIR --time 5` ran the
// checkpoint's time and said nothing. Every flag that says what the run is is refused with it,
// before the directory is read (here it holds no checkpoint at all).
TEST(Cli, RunResumeRefusesTheRunsOwnArguments) {
  const fs::path dir = Scratch() / "resumed";
  fs::create_directories(dir);
  for (const std::string& given : std::vector<std::string>{
           "one_sprig", "--time 5", "--log-step 3", "--out " + (Scratch() / "other").string(),
           "--backend xpbd", "--integrator leapfrog", "--muscles off",
           "--apply-physical-parameters", "--set gravity_y=-1", "--no-fields", "--zarr",
           "--checkpoint-every 10"}) {
    const Result r = Owval("run --resume " + dir.string() + " " + given);
    EXPECT_EQ(r.exit_code, 2) << given << ": " << r.err;
    const std::string flag = given.substr(0, given.find(' '));
    EXPECT_EQ(r.err, "owval: usage: " + (flag == "one_sprig" ? "the argument config" : flag) +
                         " cannot be given with --resume (see --help)\n");
  }
  EXPECT_FALSE(fs::exists(Scratch() / "other"));
}

// ci validate's run flags belong to --stability: given with a directory they were ignored.
TEST(Cli, ValidateRefusesTheStabilityRunsFlagsWithoutIt) {
  const fs::path dir = Scratch() / "artifacts";
  fs::create_directories(dir);
  for (const std::string& given : std::vector<std::string>{
           "--scenario one_sprig", "--log-step 5", "--out " + (Scratch() / "run").string()}) {
    const Result r = Owval("ci validate " + dir.string() + " " + given);
    EXPECT_EQ(r.exit_code, 2) << given;
    EXPECT_EQ(r.err, "owval: usage: " + given.substr(0, given.find(' ')) +
                         " needs --stability (see --help)\n");
  }
  EXPECT_FALSE(fs::exists(Scratch() / "run"));
}

TEST(Cli, MissingFileIsOneLineExitTwo) {
  const Result r = Owval("inspect /nonexistent/position_buffer.txt");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent/position_buffer.txt"), std::string::npos);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Cli, TruncatedFileNamesFileAndLineAndLeavesNoOutput) {
  const fs::path bad = Scratch() / "truncated.txt";
  const std::string text = FileBytes(kOneSprig);
  std::ofstream(bad) << text.substr(0, text.size() / 2 - 7);  // cut mid-row
  const fs::path out = Scratch() / "converted.h5";
  fs::remove(out);
  const Result r = Owval("convert " + bad.string() + " " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("truncated.txt:"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(Scratch()))
    EXPECT_EQ(e.path().filename().string().find(".converted.h5.tmp"), std::string::npos);
}

// In frame 0 too: the line named, exit 1 (the record of a failed simulation, not bad input).
TEST(Cli, NaNInTrajectoryIsRefusedAsAFailedSimulation) {
  const fs::path bad = Scratch() / "nan.txt";
  std::string text = FileBytes(kOneSprig);
  const auto row = text.find("17.535\t20.04");
  text.replace(row, 6, "nan");
  std::ofstream(bad) << text;
  const Result r = Owval("inspect " + bad.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nan.txt:12: x is not finite"), std::string::npos) << r.err;
}

// `compare a.h5 b.h5 --markdown b.h5` replaced the candidate with the report, `render a.h5 -o
// a.h5` the trajectory with a video (exit 0 both). An output that is an input of the same command
// (through a link or another spelling too) is refused before any work, and the input is kept.
TEST(Cli, AnOutputThatIsAnInputIsRefusedAndTheInputKept) {
  const fs::path dir = Scratch() / "output_is_input";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path a = dir / "a.h5", b = dir / "b.h5";
  ASSERT_EQ(Owval("convert " + kOneSprig + " " + a.string()).exit_code, 0);
  fs::copy_file(a, b);
  fs::create_symlink(b, dir / "link.h5");
  const std::string original = FileBytes(b);
  const std::string input = ": is also an input of this command";
  // A link is refused as an output whatever it points to (the rename would replace the link).
  const std::string link = ": is a symbolic link; name its target";
  for (const auto& [args, named, says] :
       std::vector<std::tuple<std::string, fs::path, std::string>>{
           {"compare " + a.string() + " " + b.string() + " --markdown " + b.string(), b, input},
           {"compare " + a.string() + " " + b.string() + " --markdown " +
                (dir / "link.h5").string(),
            dir / "link.h5", link},
           {"render " + b.string() + " --size 64x64 -o " + b.string(), b, input},
           {"render sxs " + a.string() + " " + b.string() + " --size 64x64 -o " +
                (dir / "." / "b.h5").string(),
            dir / "." / "b.h5", input},
           {"convert " + b.string() + " " + b.string(), b, input}}) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.rfind("owval: error: " + named.string() + says, 0), 0u)
        << args << ": " << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_EQ(FileBytes(b), original) << args;
  }
}

// A NaN in a trajectory's positions is the record of a failed simulation: exit 1 with one line
// naming file and line for a measurement (it was exit 2, bad input, so `check stability` never
// failed on the NaN it exists to find). `ci quick-test`'s "completed without NaN" gate fails
// (exit 1), as the checklist's item 3 does, and a NaN a simulation owval runs produces is exit 1.
TEST(Cli, NaNInACandidateIsAFailedSimulationToAMeasurementAndAFailedGateToQuickTest) {
  const fs::path dir = Scratch() / "nan_candidate";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string text = FileBytes(kOneSprig);
  std::ofstream(dir / "reference.txt") << text;
  const auto row = text.rfind("17.535\t");  // the elastic particle of the last frame
  text.replace(row, 6, "nan");
  std::ofstream(dir / "candidate.txt") << text;
  const std::string cand = (dir / "candidate.txt").string(), ref = (dir / "reference.txt").string();
  const Result quick = Owval("ci quick-test " + dir.string());
  EXPECT_EQ(quick.exit_code, 1) << quick.out << quick.err;
  EXPECT_NE(quick.out.find("FAIL"), std::string::npos) << quick.out;
  for (const std::string& args : {"ci validate " + dir.string(), "compare " + ref + " " + cand,
                                  "render " + cand + " --size 64x64 -o " + (dir / "x.mp4").string(),
                                  "check stability " + cand, "inspect " + cand}) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.out << r.err;
    EXPECT_EQ(r.err.rfind("owval: error: " + cand + ":", 0), 0u) << args << ": " << r.err;
    EXPECT_NE(r.err.find(":4679: z is not finite (NaN or Inf): the simulation that wrote this "
                         "file failed"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "x.mp4"));
}

TEST(Cli, ConvertRoundTripThroughHdf5) {
  const fs::path h5 = Scratch() / "one_sprig.h5", back = Scratch() / "back.txt";
  ASSERT_EQ(Owval("convert " + kOneSprig + " " + h5.string()).exit_code, 0);
  ASSERT_EQ(Owval("convert " + h5.string() + " " + back.string()).exit_code, 0);
  EXPECT_EQ(FileBytes(back), FileBytes(kOneSprig));  // byte-identical at Sibernetic's 6 digits
}

TEST(Cli, CompareExitCodes) {
  EXPECT_EQ(Owval("compare " + kOneSprig + " " + kOneSprig).exit_code, 0);
  // A copy whose elastic particle's y is 6% higher fails the frame gate.
  const fs::path h5 = Scratch() / "ref.h5";
  ASSERT_EQ(Owval("convert " + kOneSprig + " " + h5.string()).exit_code, 0);
  std::string text = FileBytes(kOneSprig);
  std::string scaled;
  std::istringstream in(text);
  int line = 0;
  for (std::string row; std::getline(in, row); ++line) {
    if (line >= 11 && row.find("\t2.1") != std::string::npos) {
      std::istringstream fields(row);
      double x, y, z;
      std::string type;
      fields >> x >> y >> z >> type;
      char buffer[128];
      std::snprintf(buffer, sizeof buffer, "%g\t%g\t%g\t%s", x, y * 1.06, z, type.c_str());
      row = buffer;
    }
    scaled += row + "\n";
  }
  const fs::path cand = Scratch() / "scaled.txt";
  std::ofstream(cand) << scaled;
  const Result r = Owval("compare " + h5.string() + " " + cand.string() + " --frames 0,15,100,200");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("failing frames 0, 15, 100, 200"), std::string::npos) << r.out;
  // Scaled from frame 0 on: it also starts elsewhere.
  EXPECT_NE(r.out.find("FAIL (failed: initial_state, frames"), std::string::npos) << r.out;
}

// --frames past the reference's end said "has no candidate frame at t = ? s".
TEST(Cli, ASampleFramePastTheReferencesEndIsNamed) {
  const Result r = Owval("compare " + kOneSprig + " " + kOneSprig + " --frames 0,99999999999");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sample frame 99999999999 is past the reference's end (2500 frames"),
            std::string::npos)
      << r.err;
}

TEST(Cli, UnknownOptionIsBadUsage) { EXPECT_EQ(Owval("inspect --no-such-flag x").exit_code, 2); }

}  // namespace

namespace {

TEST(CliPredict, ReconcileNamesTheQuarterFactor) {
  const fs::path p = Scratch() / "p.json", p4 = Scratch() / "p4.json";
  ASSERT_EQ(Owval("predict one_sprig -o " + p.string()).exit_code, 0);
  EXPECT_EQ(Owval("reconcile " + p.string() + " " + kOneSprig).exit_code, 0);
  ASSERT_EQ(Owval("predict one_sprig --no-quarter-factor -o " + p4.string()).exit_code, 0);
  const Result r = Owval("reconcile " + p4.string() + " " + kOneSprig);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("0.25 factor"), std::string::npos) << r.out;
}

TEST(CliPredict, ReconcileRefusesAToleranceForAnUnknownQuantity) {
  const fs::path p = Scratch() / "p_tolerance.json";
  ASSERT_EQ(Owval("predict one_sprig -o " + p.string()).exit_code, 0);
  const std::string reconcile = "reconcile " + p.string() + " " + kOneSprig + " --tolerance ";
  const Result misspelt = Owval(reconcile + "equilibrum=0.001");
  EXPECT_EQ(misspelt.exit_code, 2) << misspelt.out;
  EXPECT_EQ(misspelt.err.find('\n'), misspelt.err.size() - 1) << "one line: " << misspelt.err;
  EXPECT_NE(misspelt.err.find("unknown quantity 'equilibrum'"), std::string::npos) << misspelt.err;
  EXPECT_NE(misspelt.err.find("half_amplitude"), std::string::npos) << misspelt.err;  // known
  const Result nameless = Owval(reconcile + "=0.001");
  EXPECT_EQ(nameless.exit_code, 2) << nameless.out;
  EXPECT_NE(nameless.err.find("the quantity is missing"), std::string::npos) << nameless.err;
  EXPECT_EQ(Owval(reconcile + "half_amplitude=0.5").exit_code, 0);
}

TEST(CliPredict, APredictionThatIsNotFiniteIsRefusedNamingTheConstant) {
  for (const char* set : {"time_step_s=1", "elasticity_coefficient=0"}) {
    const fs::path p = Scratch() / "p_not_finite.json";
    fs::remove(p);
    const Result r = Owval("predict one_sprig --set " + std::string(set) + " -o " + p.string());
    EXPECT_EQ(r.exit_code, 2) << set << ": " << r.out;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
    const std::string name = std::string(set).substr(0, std::string(set).find('='));
    EXPECT_NE(r.err.find("not finite"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(name + " = "), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(p));
  }
}

TEST(CliRun, AQuietRunThatFailsTheStabilityGateStillSaysWhy) {
  const fs::path out = Scratch() / "stability_quiet";
  fs::remove_all(out);
  const Result r = Owval(
      "run one_sprig --set gravity_y=-1e5 --stability --time 0.004 "
      "--log-step 10 -o " +
      out.string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  EXPECT_NE(r.err.find("stability gate failed: "), std::string::npos) << r.err;
}

TEST(CliFit, ExternalCommandModeFitsOneSprigThroughOwvalRun) {
  const fs::path dir = Scratch() / "fit_external";
  const std::string command =
      std::string(OWVAL_EXE) +
      " --quiet run one_sprig --time 0.05 --log-step 1 --no-fields --out {out} --set "
      "elasticity_coefficient={elasticity_coefficient}";
  const Result r = Owval(
      "fit one_sprig --param elasticity_coefficient=1.62e8:log --target "
      "period=0.7246e-3:scale=0.725e-3 --target half_amplitude=1.694:scale=1.694:weight=0.25 "
      "--command '" +
      command + "' -o " + dir.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto h = nlohmann::json::parse(r.out);
  EXPECT_TRUE(h["converged"].get<bool>());
  EXPECT_LE(h["iterations"].size(), 7u);
  EXPECT_NEAR(h["final"]["parameters"]["elasticity_coefficient"].get<double>(), 3e8, 3e8 * 0.01);
}

TEST(CliRun, UnknownBackendIsExitTwoListingTheKnownOnes) {
  const fs::path out = Scratch() / "unknown_backend";
  const Result r = Owval("run one_sprig --time 0.0001 --backend nosuch --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown backend 'nosuch'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pcisph"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(out / "position_buffer.txt"));
}

// Every command that writes a file or directory takes -o/--out, as a user types it anywhere.
TEST(CliRun, TakesTheShortOutputFlagAsEveryOtherCommandDoes) {
  const fs::path out = Scratch() / "short_out";
  const Result r = Owval("run one_sprig --time 0.0001 --quiet -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "trajectory.h5"));
}

TEST(CliRun, OwvalIsAnAliasOfPcisph) {
  const fs::path out = Scratch() / "alias_backend";
  const Result r =
      Owval("run one_sprig --time 0.0001 --backend owval --json --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["backend"], "pcisph");
}

TEST(CliRun, XpbdBackendRunsAndIsNotReferenceEquivalent) {
  const fs::path out = Scratch() / "xpbd_backend";
  const Result r = Owval(
      "run one_sprig --time 0.001 --backend xpbd --set xpbd_iterations=2 --json "
      "--out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["backend"], "xpbd");
  EXPECT_EQ(j["reference_equivalent"], false);
  EXPECT_EQ(j["steps"], 50);
  EXPECT_EQ(Owval("run one_sprig --time 0.001 --backend xpbd --set xpbd_iterations=0 --out " +
                  out.string())
                .exit_code,
            2);
}

// The adaptive scheme's record is written frame by frame beside the trajectory (memory does not
// grow with the run), one entry per frame, and is part of the run's outputs.
TEST(CliRun, WcsphStepLogHasOneEntryPerFrame) {
  const fs::path out = Scratch() / "wcsph_step_log";
  const Result r = Owval(
      "run hydrostatic_tank --backend wcsph --time 0.0004 --log-step 5 --json "
      "--out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(r.out);
  const auto log = nlohmann::json::parse(FileBytes(out / "step_log.json"));
  EXPECT_EQ(log["backend"], "wcsph");
  ASSERT_EQ(log["frames"].size(), summary["frames"].get<std::size_t>());
  EXPECT_TRUE(log["frames"].back().contains("max_density_variation"));
  EXPECT_EQ(summary["outputs"].back(), (out / "step_log.json").string());
}

// Issue 18 items 12 and 14: usage errors are one short line; particle indices are not wrapped;
// --max-memory bounds what an input may allocate.
TEST(Cli, UsageErrorsAreOneLineAndIndicesAreChecked) {
  const std::string traj = kOneSprig;
  for (const std::string& particle : {std::string("-1"), std::string(309, '9')}) {
    const Result r = Owval("inspect --particle " + particle + " " + traj);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err,
              "owval: usage: --particle: expected a particle index (0, 1, 2, ...) (see "
              "--help)\n");
  }
  const Result unknown = Owval("compare a b --frobnicate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(unknown.err.find('\n'), unknown.err.size() - 1) << unknown.err;
  const Result budget = Owval("--max-memory 1K inspect " + traj);
  EXPECT_EQ(budget.exit_code, 2);
  EXPECT_NE(budget.err.find("more than the memory budget of 1024 bytes (--max-memory)"),
            std::string::npos)
      << budget.err;
  EXPECT_EQ(Owval("--max-memory 12Q inspect " + traj).exit_code, 2);
  EXPECT_EQ(Owval("--max-memory 256M inspect " + traj).exit_code, 0);  // needs 115 MB
}

// A number out of its range is named with what was expected and what was found, in one short
// line (CLI11's own checks printed their bounds as 300-digit doubles, and "abc" as out of range).
TEST(Cli, NumbersOutOfRangeSayWhatWasExpected) {
  const Result zero = Owval("run demo1 --out x --log-step 0");
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_EQ(zero.err, "owval: usage: --log-step: expected a number > 0, found '0' (see --help)\n");
  const Result word = Owval("bench backends owval --scenario demo1 --repeat abc");
  EXPECT_EQ(word.exit_code, 2);
  EXPECT_EQ(word.err, "owval: usage: --repeat: expected a number > 0, found 'abc' (see --help)\n");
  const Result negative = Owval("fit one_sprig --param a=1 -o x --patience -1");
  EXPECT_EQ(negative.exit_code, 2);
  EXPECT_EQ(negative.err,
            "owval: usage: --patience: expected a number >= 0, found '-1' (see --help)\n");
  EXPECT_EQ(Owval("fit one_sprig --param a=1 -o x --patience 0 --help").exit_code, 0);
  // A thread count the machine cannot start: one line before any work, not libgomp's crash.
  const Result threads = Owval("run one_sprig --out x --threads 100000");
  EXPECT_EQ(threads.exit_code, 2);
  EXPECT_EQ(threads.err,
            "owval: usage: --threads: Value 100000 not in range 0 to 1024 (see --help)\n");
  EXPECT_EQ(Owval("bench backends owval --scenario demo1 --threads 0").exit_code, 2);
}

// bench io writes its generated files where --dir says and removes them, and the directories it
// had to make for them, however it ends (it left an empty --dir tree behind before).
TEST(CliBench, IoRemovesItsFilesAndTheDirectoriesItMade) {
  const fs::path root = Scratch() / "bench_io";
  fs::remove_all(root);
  fs::create_directories(root);
  const Result r = Owval("-q bench io --size-mb 1 --dir " + (root / "new/deeper").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_empty(root));
  const Result kept = Owval("-q bench io --size-mb 1 --keep --dir " + (root / "kept").string());
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_TRUE(fs::exists(root / "kept/owval_bench_trajectory.h5"));
  std::ofstream(root / "file") << "x";  // a file where the directory would go
  const Result blocked = Owval("-q bench io --size-mb 1 --dir " + (root / "file/sub").string());
  EXPECT_EQ(blocked.exit_code, 2) << blocked.err;
  EXPECT_EQ(std::count(blocked.err.begin(), blocked.err.end(), '\n'), 1) << blocked.err;
  fs::remove_all(root);
}

// Numbers that were taken and misread: a negative count wrapped to 2^64 - 1, an opacity of NaN,
// a frame edge past int's range read by sscanf, a generated file of -5 MB (which ran until
// killed), a stability gate's tolerance of NaN (which passed every frame). Each is now one line,
// exit 2, and nothing written.
TEST(Cli, HostileNumbersAreOneLineExitTwoAndWriteNothing) {
  const std::string traj = kOneSprig;
  const fs::path out = Scratch() / "hostile";
  fs::remove_all(out);
  fs::create_directories(out);
  const std::string video = (out / "a.mp4").string(), frames = (out / "f").string();
  for (const std::string& args : std::vector<std::string>{
           "render " + traj + " -o " + video + " --size 99999999999999999999x10",
           "render " + traj + " -o " + video + " --size 20000x100",
           "render " + traj + " -o " + video + " --liquid-opacity nan",
           "render " + traj + " -o " + video + " --liquid-opacity -3",
           "render " + traj + " -o " + video + " --max-frames -1",
           "frames " + traj + " " + traj + " -o " + frames + " --at -1",
           "compare " + traj + " " + traj + " --frames 0,-1",
           "compare " + traj + " " + traj + " --scale inf",
           "bench io --size-mb -5 --dir " + out.string(),
           "bench io --size-mb 99999999999 --dir " + out.string(),
           "bench engine one_sprig --steps -1",
           "bench render --frames -2",
           "check stability " + traj + " --box-tolerance nan",
           "check stability " + traj + " --speed-limit -1",
           "run one_sprig --out " + out.string() + " --checkpoint-every -1",
       }) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << args << ": " << r.err;
    EXPECT_TRUE(fs::is_empty(out)) << args;
  }
}

}  // namespace
// wrote one PNG but three entries: an empty, repeated or out-of-range list is one line, exit 2,
// and nothing written.
TEST(Cli, FramesRefuseAnEmptyOrRepeatedAtList) {
  const std::string traj = kOneSprig;
  const fs::path out = Scratch() / "frames_at";
  fs::remove_all(out);
  for (const std::string at : {"''", "0,0,0", "0,", "0,15,9999"}) {
    const Result r = Owval("frames " + traj + " " + traj + " --at " + at + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << at << ": " << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << at << ": " << r.err;
    // '' is refused by the parser (a usage line), the others by the frame list's reader.
    EXPECT_NE(r.err.find(at == "''" ? "owval: usage: --at:" : "owval: error:"), std::string::npos)
        << at << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << at;
  }
}

// render -o EXISTING_DIR (and render sxs) rendered for seconds, then failed "cannot rename into
// place: Is a directory". -o is the MP4 file: a directory is refused before any work, by name.
TEST(Cli, RenderIntoAnExistingDirectoryIsRefusedBeforeWork) {
  const std::string traj = kOneSprig;
  const fs::path dir = Scratch() / "render_dir";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const std::string& args : {"render " + traj, "render sxs " + traj + " " + traj}) {
    const Result r = Owval(args + " --size 64x64 -o " + dir.string());
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(r.err,
              "owval: error: " + dir.string() + ": is a directory; expected a file to write\n")
        << args;
    EXPECT_TRUE(fs::is_empty(dir)) << args;
  }
}

// bench engine|render|gradient --json-out /proc/x.json ran the whole benchmark (as root,
// access()
// allowed /proc), then exited 2: the path is now refused before the benchmark, nothing on stdout.
TEST(Cli, BenchRefusesAnUnwritableJsonOutBeforeRunning) {
  if (!fs::is_directory("/proc/self")) GTEST_SKIP() << "no /proc";
  for (const std::string& args :
       std::vector<std::string>{"bench engine one_sprig --steps 1 --json-out /proc/x.json",
                                "bench render --frames 1 --json-out /proc/r.json",
                                "bench gradient one_sprig --steps 1 --json-out /proc/g.json"}) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("cannot be written: /proc"), std::string::npos) << args << ": " << r.err;
  }
}

// fit with LOWER > UPPER exited 1 with Ceres' multi-line message and a history of loss 0; fit
// --threshold nan, --log-step 0, --time -1 and bench gradient --alpha-density nan or -1 were
// taken. Each is now one line, exit 2, before any work (nothing on stdout, no output folder).
TEST(Cli, FitAndBenchGradientRefuseBadNumbersBeforeWork) {
  const fs::path out = Scratch() / "fit_numbers";
  fs::remove_all(out);
  const std::string fit = "fit one_sprig --target period=0.7246e-3:scale=0.725e-3 -o " +
                          out.string() + " --param elasticity_coefficient=1.62e8:log";
  for (const std::string& args : std::vector<std::string>{
           fit + ":1e9:1e8",
           fit + " --threshold nan",
           fit + " --threshold -1",
           fit + " --log-step 0",
           fit + " --time -1",
           "bench gradient one_sprig --steps 1 --alpha-density nan",
           "bench gradient one_sprig --steps 1 --alpha-density -1",
       }) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

// fit with an unknown --param or --target left the empty output folder it had created.
TEST(Cli, FailedFitLeavesNoFolderBehind) {
  const fs::path out = Scratch() / "fit_failed" / "deeper";
  fs::remove_all(out.parent_path());
  for (const std::string& args :
       std::vector<std::string>{"--param nosuch=1:log --target period=0.7246e-3:scale=0.725e-3",
                                "--param elasticity_coefficient=1.62e8:log --target nosuch=1"}) {
    const Result r = Owval("fit one_sprig " + args + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out.parent_path())) << args;
  }
}

// Errors named the temporary instead of the user's path (render -o /proc/x.mp4 said
// "/proc/.x.mp4.tmp.32621.0: cannot open for writing", pipeline -o /proc/pp "[/proc/.pp.tmp...]"),
// and --size 101x101 failed after the trajectory was read, naming the temporary, leaving the
// folder it had made. Each is one line naming what the user typed, before any work.
TEST(Cli, OutputErrorsNameTheUsersPathAndOddVideoSizesAreRefusedFirst) {
  const std::string traj = kOneSprig;
  const fs::path out = Scratch() / "odd_size";
  fs::remove_all(out);
  for (const std::string& args :
       {"render " + traj + " --size 101x101 -o " + (out / "x.mp4").string(),
        "render sxs " + traj + " " + traj + " --size 64x33 -o " + (out / "x.mp4").string()}) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.rfind("owval: error: --size ", 0), 0u) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
  if (!fs::is_directory("/proc/self")) GTEST_SKIP() << "no /proc";
  for (const auto& [args, named] : std::vector<std::pair<std::string, std::string>>{
           {"render " + traj + " --size 64x64 -o /proc/x.mp4", "/proc/x.mp4"},
           {"pipeline one_sprig -o /proc/pp", "/proc/pp"}}) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.rfind("owval: error: " + named, 0), 0u) << r.err;
    EXPECT_EQ(r.err.find(".tmp"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  }
}

// run -o /proc/x named position_buffer.txt, frames/predict/scenario generate -o /proc/x...
// printed libstdc++'s "filesystem error: cannot create directories: ... [/proc/x]", convert to
// /sys/x.zarr named a file inside the store: one line naming the directory the user typed and
// what stops it (/proc takes no new entries), exit 2.
TEST(Cli, AnOutputUnderProcNamesTheDirectoryAndWhatStopsIt) {
  if (!fs::is_directory("/proc/self")) GTEST_SKIP() << "no /proc";
  const std::string traj = kOneSprig;
  for (const auto& [args, named] : std::vector<std::pair<std::string, std::string>>{
           {"run one_sprig --time 0.0001 -o /proc/owval_x", "/proc/owval_x"},
           {"run one_sprig --time 0.0001 -o /proc/owval_x/y", "/proc/owval_x"},
           {"frames " + traj + " " + traj + " --at 0 -o /proc/owval_x", "/proc/owval_x"},
           {"predict one_sprig -o /proc/owval_x/p.json", "/proc/owval_x"},
           {"scenario generate one_sprig -o /proc/owval_x/c.txt", "/proc/owval_x"},
           {"convert " + traj + " /proc/owval_x.zarr", "/proc/owval_x.zarr"},
           {"fit one_sprig --param elasticity_coefficient=1.62e8:log --target "
            "period=0.7246e-3:scale=0.725e-3 --time 0.005 -o /proc/owval_x",
            "/proc/owval_x"}}) {
    const Result r = Owval(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.rfind("owval: error: " + named + ": cannot be created: /proc ", 0), 0u)
        << args << ": " << r.err;
    EXPECT_EQ(r.err.find("filesystem error"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  }
}

// render --max-frames 0 rendered every frame, undocumented. 0 is the default and means no cap
// (as "0: full tape", "0: never" on other flags): the help says so.
TEST(Cli, MaxFramesHelpSaysZeroIsEveryFrame) {
  for (const std::string command : {"render", "render sxs"}) {
    const Result r = Owval(command + " --help");
    EXPECT_EQ(r.exit_code, 0) << command;
    EXPECT_NE(r.out.find("0, the default: every frame"), std::string::npos) << r.out;
  }
  const Result pipeline = Owval("pipeline --help");
  EXPECT_NE(pipeline.out.find("(0: every frame)"), std::string::npos) << pipeline.out;
}

}  // namespace owval::testing
