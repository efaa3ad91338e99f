// Hostile values of the flags every command shares in kind: a NAME=NUMBER given twice (--set,
// --param), an empty output path (-o '', --markdown '', ...), numbers strtod reads but a person
// does not mean (0x10, inf, " 1"), and inspect's time window. Each is one line naming the flag,
// exit 2, and nothing written.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

// An empty directory of its own, for commands run inside it (cd DIR && owval ...).
fs::path FreshDirectory(const std::string& name) { return TestScratch(name); }

std::vector<std::string> Entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    names.push_back(e.path().lexically_relative(dir).string());
  return names;
}

// `owval --quiet ARGS` run inside `dir`.
Result OwvalIn(const fs::path& dir, const std::string& args) {
  return RunCaptured("cd '" + dir.string() + "' && " + OWVAL_EXE + " --quiet " + args);
}

// Exit 2 with one line on stderr saying `says`.
void ExpectOneLineRefusal(const Result& r, const std::string& says, const std::string& command) {
  EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << command << ": one line: " << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << command << ": " << r.err;
}

// Each command run in `dir` is refused with one line saying `says`, prints nothing and leaves
// nothing in `dir`.
void ExpectEachRefusedLeavingNothing(const fs::path& dir, const std::vector<std::string>& commands,
                                     const std::string& says) {
  for (const std::string& c : commands) {
    const Result r = OwvalIn(dir, c);
    ExpectOneLineRefusal(r, says, c);
    EXPECT_EQ(r.out, "") << c;
    EXPECT_TRUE(Entries(dir).empty()) << c << " left " << Entries(dir).front();
  }
}

TEST(HostileFlags, ARepeatedSetOrParamNameIsRefusedByEveryCommand) {
  const fs::path dir = FreshDirectory("repeated");
  const std::string twice = " --set elasticity_coefficient=1e8 --set elasticity_coefficient=2e8";
  const std::vector<std::string> commands = {
      "predict one_sprig" + twice,
      "predict one_sprig --param rest_length_cu=2 --param rest_length_cu=3",
      "run one_sprig --time 0.001 --out " + (dir / "run").string() + twice,
      "scenario generate one_sprig -o " + (dir / "c.txt").string() +
          " --param rest_length_cu=2 --param rest_length_cu=3"};
  for (const std::string& c : commands) {
    const Result r = Owval(c);
    ExpectOneLineRefusal(r, "is given twice", c);
    EXPECT_EQ(r.out, "") << c;
  }
  EXPECT_TRUE(Entries(dir).empty());
}

// Commands read an empty path as "not given": `predict -o ''` printed and exited 0, `compare
// --markdown ''` too, `pipeline -o ''` wrote reports/one_sprig into the working directory.
TEST(HostileFlags, AnEmptyOutputPathIsRefusedByEveryCommandBeforeWork) {
  const fs::path dir = FreshDirectory("empty_out");
  const std::string traj = kOneSprig;
  const std::vector<std::string> commands = {
      "predict one_sprig -o ''",
      "reconcile p.json " + traj + " -o ''",
      "scenario generate one_sprig -o ''",
      "run one_sprig --time 0.001 -o ''",
      "convert " + traj + " ''",
      "compare " + traj + " " + traj + " --markdown ''",
      "render " + traj + " -o ''",
      "render sxs " + traj + " " + traj + " -o ''",
      "frames " + traj + " " + traj + " --at 0 -o ''",
      "fit one_sprig --param elasticity_coefficient=1.62e8:log --target period=7e-4 -o ''",
      "gradcheck -o ''",
      "pipeline one_sprig -o ''",
      "checklist . --scenario one_sprig --markdown ''",
      "ci validate --stability 10s -o ''",
      "bench io --json-out ''",
      "bench io --dir ''",
      "bench backends owval --scenario one_sprig --markdown ''",
      "bench backends owval --scenario one_sprig --json ''"};
  ExpectEachRefusedLeavingNothing(dir, commands, "expected a path to write, found an empty one");
}

// An empty input (a backends file, a cache, a manifest, a reference, a scenario) was read as
// "not given": `compare --manifest ''` compared with the defaults and exited 0.
TEST(HostileFlags, AnEmptyInputNameIsRefusedByEveryCommand) {
  const fs::path dir = FreshDirectory("empty_in");
  const std::string traj = kOneSprig;
  const std::vector<std::string> commands = {
      "compare " + traj + " " + traj + " --manifest ''",
      "compare " + traj + " " + traj + " --cache ''", "compare owval owval --reference-dir ''",
      "compare owval owval --sibernetic ''", "backends show owval --backends ''",
      "checklist . --scenario ''", "checklist . --manifest '' --reference " + traj,
      "checklist . --reference ''", "ci validate . --reference ''",
      "ci validate --stability 10s --scenario ''",
      "fit one_sprig --param elasticity_coefficient=1.62e8:log --target period=7e-4 "
      "--reference ''",
      "bench backends owval --scenario ''",
      "bench backends owval --scenario one_sprig --reference-dir ''",
      // Positionals: each said something else ("no such scenario", "cannot open file").
      "scenario show ''", "run '' --out x", "predict ''", "reconcile '' " + traj, "pipeline ''",
      "inspect ''", "convert '' x.h5", "compare '' " + traj, "render '' -o x.mp4",
      "bench engine ''"};
  ExpectEachRefusedLeavingNothing(dir, commands, "expected a path or name, found an empty one");
}

// A benchmark of no steps or frames said something else ("duration 0 s ... gives 0 steps", "the
// trajectory has no frame to render"): the line names the flag.
TEST(HostileFlags, BenchCountsOfZeroNameTheFlag) {
  const fs::path dir = FreshDirectory("bench_zero");
  for (const std::string& c :
       {std::string("bench engine one_sprig --steps 0"),
        std::string("bench engine one_sprig --steps 00"), std::string("bench render --frames 0")}) {
    const Result r = OwvalIn(dir, c);
    ExpectOneLineRefusal(r, "expected a whole number >= 1, found '0", c);
    EXPECT_TRUE(Entries(dir).empty()) << c;
  }
}

TEST(HostileFlags, InspectWindowMessagesNameTheFlagsAndTheTimes) {
  struct Case {
    std::string flags, says;
  };
  const std::vector<Case> cases = {
      {"--from 0.03 --to 0.01", "--from 0.03 s --to 0.01 s: expected --from before --to"},
      {"--from 100", "--from 100 s: the window holds 0 frame(s) of the trajectory's t = 0 .. "},
      {"--to 0", "--to 0 s: the window holds 1 frame(s)"},
      {"--from 0x10", "--from: expected a number >= 0, found '0x10'"},
      {"--to ' 1'", "--to: expected a number >= 0, found ' 1'"}};
  for (const Case& c : cases) {
    const std::string command = "inspect " + kOneSprig + " " + c.flags;
    const Result r = Owval(command);
    ExpectOneLineRefusal(r, c.says, command);
  }
}

// strtod (and std::stod) read "0x10" as 16, "inf", "nan" and " 1": --set, --param and --target
// take decimal numbers only, through one parser.
TEST(HostileFlags, NumbersAreDecimalOnlyInSetParamAndTarget) {
  const fs::path dir = FreshDirectory("numbers");
  const std::string fit = "fit one_sprig --time 0.002 -o " + (dir / "fit").string();
  const std::vector<std::string> commands = {
      "predict one_sprig --set elasticity_coefficient=0x10",
      "predict one_sprig --set 'elasticity_coefficient= 1e8'",
      "predict one_sprig --param rest_length_cu=0x10",
      "predict one_sprig --param rest_length_cu=inf",
      "scenario generate one_sprig -o " + (dir / "c.txt").string() + " --param rest_length_cu=1e",
      "run one_sprig --time 0.001 --out " + (dir / "run").string() +
          " --set elasticity_coefficient=nan",
      fit + " --param elasticity_coefficient=0x1p27:log --target period=7e-4",
      fit + " --param elasticity_coefficient=1.6e8:log --target period=0x1p-10",
      fit + " --param elasticity_coefficient=1.6e8:log --target 'period=7e-4:scale= 1'"};
  for (const std::string& c : commands) {
    const Result r = Owval(c);
    EXPECT_EQ(r.exit_code, 2) << c << "\n" << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << c << ": one line: " << r.err;
    EXPECT_NE(r.err.find("expected"), std::string::npos) << c << ": " << r.err;
  }
  EXPECT_TRUE(Entries(dir).empty());
}

// CLI11 read an integer flag's "010" as octal and "0x10" as hex, and `run --time` took strtod's
// hex floats: `--log-step 010` logged every 8 steps and `compare --particle 010` gated particle 8,
// both exit 0. Every number on the command line is decimal: leading zeros are zeros.
TEST(HostileFlags, EveryNumberFlagIsDecimal) {
  const fs::path dir = FreshDirectory("decimal");
  const std::string out = " -o " + (dir / "run").string();
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"run one_sprig --time 0.001 --log-step 0x10" + out,
       "--log-step: expected a number > 0, found '0x10'"},
      {"run one_sprig --time 0x1p-6" + out, "--time: expected a decimal number, found '0x1p-6'"},
      {"run one_sprig --time 0.001 --threads 0x2" + out, "--threads: expected a whole number"},
      {"run one_sprig --time 0.001 --checkpoint-every -1" + out,
       "--checkpoint-every: expected a whole number >= 0"},
      {"compare " + kOneSprig + " " + kOneSprig + " --particle 0x1",
       "--particle: expected a particle index"},
      {"fit one_sprig --max-iterations 0x10" + out, "--max-iterations: expected a whole number"},
      {"gradcheck one_sprig --directions 0x10" + out, "--directions: expected a whole number"},
      {"bench io --hdf5-level 0x9 --size-mb 1", "--hdf5-level: expected a whole number"}};
  for (const auto& [command, says] : refused)
    ExpectOneLineRefusal(OwvalIn(dir, command), says, command);
  EXPECT_TRUE(Entries(dir).empty());
  // Leading zeros: ten, not eight.
  const Result run = OwvalIn(dir, "run one_sprig --time 0.001 --log-step 010" + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream text(dir / "run/position_buffer.txt");
  std::string line;
  for (int n = 0; n < 11; ++n) std::getline(text, line);
  EXPECT_EQ(line, "10");  // the header's log step (README of ../shared/reference)
  const Result compare = Owval("compare " + kOneSprig + " " + kOneSprig + " --particle 00");
  EXPECT_EQ(compare.exit_code, 0) << compare.err;
  EXPECT_NE(compare.out.find("particle 0 y"), std::string::npos) << compare.out;
  fs::remove_all(dir);
}

// Text values given empty were read as "not given": `pipeline --candidate ''` judged owval's own
// engine as the candidate and said ready; `compare --frames ''` gated every frame.
TEST(HostileFlags, AnEmptyTextValueIsRefusedByEveryOption) {
  const fs::path dir = FreshDirectory("empty_text");
  const std::string fit =
      "fit one_sprig --param elasticity_coefficient=1.62e8:log --target "
      "period=7e-4 --time 0.002 -o fit";
  const std::vector<std::string> commands = {
      "pipeline one_sprig -o p --candidate ''",
      "compare " + kOneSprig + " " + kOneSprig + " --frames ''",
      "render " + kOneSprig + " -o v.mp4 --connections ''",
      "checklist . --reference " + kOneSprig + " --git-range ''",
      fit + " --command ''",
      fit + " --gradient analytic --reference " + kOneSprig + " --loss-group ''"};
  ExpectEachRefusedLeavingNothing(dir, commands, "found an empty one");
}

// A fit's step and clip were taken as given (a learning rate of -1 or 0 ran, NaN ran one
// iteration and left a history of no evaluation), and --max-iterations -1 reached Ceres, whose
// log lines went to stderr.
TEST(HostileFlags, FitStepsAreCheckedBeforeWork) {
  const fs::path dir = FreshDirectory("fit_steps");
  const std::string fit =
      "fit one_sprig --param elasticity_coefficient=1.62e8:log --target "
      "period=7e-4 --time 0.002 -o fit --solver gd";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {fit + " --learning-rate 0", "--learning-rate: expected a number > 0"},
      {fit + " --learning-rate -1", "--learning-rate: expected a number > 0"},
      {fit + " --learning-rate nan", "--learning-rate: expected a number > 0"},
      {fit + " --clip-norm -1", "--clip-norm: expected a number >= 0"},
      {fit + " --max-iterations -1", "--max-iterations: expected a whole number >= 1"},
      {fit + " --max-iterations 0", "--max-iterations: expected a whole number >= 1"}};
  for (const auto& [command, says] : cases)
    ExpectOneLineRefusal(OwvalIn(dir, command), says, command);
  EXPECT_TRUE(Entries(dir).empty());
}

// An unknown --set name listed every constant, a 314-character line cut off in the middle; a
// 300-digit scenario name said "File name too long" of a manifests path.
TEST(HostileFlags, UnknownNamesAreShortLines) {
  const Result set = Owval("predict one_sprig --set elasticity_coeficient=3e8");
  ExpectOneLineRefusal(set,
                       "unknown engine constant 'elasticity_coeficient' (nearest: "
                       "elasticity_coefficient, ",
                       "--set");
  EXPECT_LT(set.err.size(), 200u) << set.err;
  const Result scenario = Owval("scenario show " + std::string(300, '9'));
  ExpectOneLineRefusal(scenario, "no such scenario", "scenario show 300 digits");
  EXPECT_EQ(scenario.err.find("too long"), std::string::npos) << scenario.err;
}

// An interrupted fit exited 1, as one that did not converge: 128 + the signal, as `run`.
TEST(HostileFlags, AnInterruptedFitExits130WithItsHistory) {
  const fs::path dir = FreshDirectory("fit_interrupted");
  std::string line = "timeout --preserve-status -s INT 2 ";
  line += OWVAL_EXE;
  // Gradient descent with no threshold to stop at: it runs its 1,000 iterations unless stopped.
  line +=
      " --quiet fit one_sprig --param elasticity_coefficient=1.62e8:log --target "
      "period=7.246e-4:scale=7.25e-4 --time 0.05 --solver gd --threshold 0 --max-iterations "
      "1000 -o " +
      (dir / "fit").string();
  const Result r = RunCaptured(line);
  EXPECT_EQ(r.exit_code, 130) << r.err << r.out;
  EXPECT_TRUE(fs::exists(dir / "fit" / "history.json"));
}

// Probe round: `scenario generate -o DIR` failed only at the rename ("cannot rename into place: Is
// a directory"), -o /proc/x with "No such file or directory"; `ci validate --stability 0x10s`
// started a 16 s run.
TEST(HostileFlags, ScenarioOutputsAndStabilityDurationsAreCheckedBeforeWork) {
  const fs::path dir = FreshDirectory("probe");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"scenario generate one_sprig -o " + dir.string(), "is a directory; expected a file"},
      {"scenario generate one_sprig -o /proc/owval_c.txt", "/proc accepts no new files"},
      {"ci validate --stability 0x10s --out " + (dir / "run").string(),
       "--stability '0x10s': expected a positive duration"}};
  for (const auto& [command, says] : cases) ExpectOneLineRefusal(Owval(command), says, command);
  EXPECT_TRUE(Entries(dir).empty());
}

// `ci validate --stability 10s --backend bogus` said "Directory does not exist: bogus": CLI11 took
// the unknown flag's value as the directory and checked it before naming the flag. A directory
// given with --stability was ignored.
TEST(HostileFlags, CiValidateNamesAnUnknownFlagAndRefusesADirectoryWithStability) {
  const fs::path dir = FreshDirectory("ci_validate");
  const std::string out = " --out " + (dir / "run").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"ci validate --stability 10s --backend bogus" + out, "not expected: --backend"},
      {"ci validate " + dir.string() + " --stability 10s" + out, "not both"},
      {"ci validate " + (dir / "missing").string(),
       "missing, expected a directory of PR artifacts (reference.*, candidate.*)"}};
  for (const auto& [command, says] : cases) {
    const Result r = Owval(command);
    ExpectOneLineRefusal(r, says, command);
    EXPECT_EQ(r.err.find("bogus"), std::string::npos) << command << ": " << r.err;
  }
  EXPECT_TRUE(Entries(dir).empty());
  // A FIFO was "Directory does not exist" (validate) and CLI11's "Directory is actually a file"
  // (quick-test, a usage error): both now say what it is, as every file input does.
  const fs::path fifo = FreshDirectory("ci_fifo") / "artifacts";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const char* command : {"ci validate ", "ci quick-test ", "checklist "})
    ExpectOneLineRefusal(Owval(command + fifo.string()),
                         "is a FIFO (named pipe), expected a directory of PR artifacts", command);
}

// `bench io` generates its text file, then parses it: SIGTERM during the parse left the file
// (100 MB here, 500 MB by default) behind, since the signal's default action skips destructors.
TEST(HostileFlags, BenchIoKilledLeavesNothingBehind) {
  const fs::path dir = FreshDirectory("bench_io") / "made";
  const fs::path text = dir / "owval_bench_position_buffer.txt";
  const std::string dir_text = dir.string();
  std::vector<std::string> args = {OWVAL_EXE,   "--quiet", "bench", "io",
                                   "--size-mb", "100",     "--dir", dir_text};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, OWVAL_EXE, &quiet, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&quiet);
  int status = 0;
  bool finished = false;
  while (!fs::exists(text) && !finished) {  // the generated file, complete, being parsed
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    finished = ::waitpid(pid, &status, WNOHANG) == pid;
  }
  ASSERT_FALSE(finished) << "bench io ended before its text file appeared";
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  const bool stopped = (WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) ||
                       (WIFEXITED(status) && WEXITSTATUS(status) == 143);
  EXPECT_TRUE(stopped) << "status " << status;
  EXPECT_FALSE(fs::exists(text));
  EXPECT_FALSE(fs::exists(dir)) << "left " << Entries(dir).size() << " entries";
}

// Hostile-input sweep, thirtieth session: what regular-file inputs already refused still blocked
// or was clobbered elsewhere. Each command runs under `timeout`: a blocked open() is exit 124.
Result OwvalWithin(const fs::path& dir, int seconds, const std::string& args) {
  return RunCaptured("cd '" + dir.string() + "' && timeout " + std::to_string(seconds) + " " +
                     OWVAL_EXE + " --quiet " + args);
}

void MakeFifo(const fs::path& path) { ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0) << path; }

// A FIFO named .owval-commit blocked every reader of its directory (the commit-marker check
// opened it before the input); a FIFO .wcon blocked kinematics (the WCON reader had no
// regular-file check).
TEST(HostileFlags, AFifoMarkerOrWconIsRefusedWithoutBlocking) {
  const fs::path dir = FreshDirectory("fifo_inputs");
  fs::copy_file(kOneSprig, dir / "a.txt");
  MakeFifo(dir / ".owval-commit");
  const Result inspect = OwvalWithin(dir, 30, "inspect a.txt");
  EXPECT_EQ(inspect.exit_code, 0) << inspect.err;  // a FIFO is no marker owval wrote
  MakeFifo(dir / "w.wcon");
  ExpectOneLineRefusal(OwvalWithin(dir, 30, "kinematics w.wcon"), "w.wcon: is a FIFO", "wcon");
}

// A worm directory's side files: a FIFO worm_motion_log.txt or a FIFO .zattrs inside the Zarr
// store blocked ci quick-test (and validate, checklist) forever; now the side-file gate fails
// naming it (exit 1).
TEST(HostileFlags, AFifoSideFileFailsItsGateWithoutBlocking) {
  const fs::path worm = fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s";
  if (ReferenceMissing(worm / "position_buffer.txt.gz")) GTEST_SKIP() << "no shared reference";
  const fs::path dir = FreshDirectory("fifo_side_files");
  ASSERT_EQ(OwvalIn(dir, "convert " + (worm / "position_buffer.txt.gz").string() + " candidate.h5")
                .exit_code,
            0);
  fs::copy_file(dir / "candidate.h5", dir / "reference.h5");
  ASSERT_EQ(OwvalIn(dir, "convert candidate.h5 trajectory.zarr").exit_code, 0);
  fs::remove(dir / "trajectory.zarr/.zattrs");
  MakeFifo(dir / "trajectory.zarr/.zattrs");
  MakeFifo(dir / "worm_motion_log.txt");
  const Result r = OwvalWithin(dir, 60, "ci quick-test .");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("worm_motion_log.txt: is a FIFO"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(".zattrs: is a FIFO"), std::string::npos) << r.out;
}

std::string Bytes(const fs::path& p) { return Slurp(p); }

// `predict C -o C`, `reconcile P T -o P` (or T) replaced their input with the JSON and exited 0;
// `run DIR/position_buffer.txt --out DIR` replaced its configuration; `predict -o DIR` failed
// only at the rename, after the work. Refused before work, the inputs byte for byte as they were.
TEST(HostileFlags, AnOutputThatIsAnInputIsRefusedBeforeWork) {
  const fs::path dir = FreshDirectory("output_is_input");
  fs::create_directories(dir / "run");
  fs::copy_file(fs::path(OWVAL_SHARED_DIR) / "reference/one_sprig/configuration", dir / "C");
  fs::copy_file(dir / "C", dir / "run/position_buffer.txt");
  fs::copy_file(kOneSprig, dir / "t.txt");
  ASSERT_EQ(OwvalIn(dir, "predict one_sprig -o p.json").exit_code, 0);
  fs::create_directories(dir / "out.json");
  fs::create_directories(dir / "pr");
  // A backends file is read by compare of backend names and by checklist --fit-backend: a
  // --markdown over it replaced it (exit 0), the implicit ./owval-backends.json as well.
  const std::string registry =
      R"({"backends": {"mine": {"command": "true {set:k} {out}", "output": "{out}/p.txt"}}})";
  std::ofstream(dir / "b.json") << registry << "\n";
  std::ofstream(dir / "owval-backends.json") << registry << "\n";
  const std::vector<std::string> names = {"C",      "run/position_buffer.txt", "t.txt", "p.json",
                                          "b.json", "owval-backends.json"};
  std::vector<std::string> before;
  for (const std::string& n : names) before.push_back(Bytes(dir / n));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"predict C -o C", "C: is also an input of this command"},
      {"predict C -o out.json", "out.json: is a directory; expected a file to write"},
      {"reconcile p.json t.txt -o p.json", "p.json: is also an input of this command"},
      {"reconcile p.json t.txt -o t.txt", "t.txt: is also an input of this command"},
      {"run run/position_buffer.txt --time 0.0001 --out run",
       "run/position_buffer.txt: is also an input of this command"},
      {"compare owval owval --scenarios one_sprig --no-cache --backends b.json --markdown b.json",
       "b.json: is also an input of this command"},
      {"compare owval owval --scenarios one_sprig --no-cache --markdown owval-backends.json",
       "owval-backends.json: is also an input of this command"},
      {"checklist pr --scenario one_sprig --backends b.json --fit-backend mine --markdown b.json",
       "b.json: is also an input of this command"}};
  for (const auto& [command, says] : cases) {
    const Result r = OwvalIn(dir, command);
    ExpectOneLineRefusal(r, says, command);
    for (std::size_t k = 0; k < names.size(); ++k)
      EXPECT_EQ(Bytes(dir / names[k]), before[k]) << command << " changed " << names[k];
  }
  EXPECT_FALSE(fs::exists(dir / "run/trajectory.h5"));
}

// bench engine and bench gradient timed CONFIG and then wrote their JSON over it (exit 0); an
// empty --max-memory ran with the default and said nothing.
TEST(HostileFlags, ABenchResultOverItsConfigurationAndAnEmptyMemorySizeAreRefused) {
  const fs::path dir = FreshDirectory("bench_json_over_config");
  fs::copy_file(fs::path(OWVAL_SHARED_DIR) / "reference/one_sprig/configuration", dir / "C");
  const std::string before = Bytes(dir / "C");
  for (const std::string command :
       {"bench engine C --steps 2 --json-out C", "bench gradient C --steps 2 --json-out ./C"}) {
    ExpectOneLineRefusal(OwvalIn(dir, command), "C: is also an input of this command", command);
    EXPECT_EQ(Bytes(dir / "C"), before) << command;
  }
  ExpectOneLineRefusal(OwvalIn(dir, "--max-memory '' inspect " + kOneSprig),
                       "expected a size such as 512M or 2G", "--max-memory ''");
}

// A candidate whose frame 848 is corrupt: frames drew frame 0, committed frame_0.png and
// frames.json, then read every frame for its gate and exited 2 with the directory in place.
TEST(HostileFlags, FramesRefusesACorruptFrameBeforeWritingAny) {
  const fs::path dir = FreshDirectory("frames_corrupt");
  ASSERT_EQ(OwvalIn(dir, "convert " + kOneSprig + " c.h5").exit_code, 0);
  std::string bytes = Bytes(dir / "c.h5");
  bytes[bytes.size() / 3] = '\0';  // inside a deflated chunk of positions, past frame 0's
  std::ofstream(dir / "c.h5", std::ios::binary | std::ios::trunc) << bytes;
  const Result inspect = OwvalIn(dir, "inspect c.h5");
  ASSERT_NE(inspect.err.find("cannot read frame"), std::string::npos) << inspect.err;
  const std::string command = "frames " + kOneSprig + " c.h5 --at 0 --size 64x36 -o fr";
  ExpectOneLineRefusal(OwvalIn(dir, command), "cannot read frame", command);
  EXPECT_FALSE(fs::exists(dir / "fr"));
}

// A fit writes configuration.txt beside its history: `fit DIR/configuration.txt -o DIR` replaced
// the configuration it was fitting (exit 1 after the evaluations, the input gone).
TEST(HostileFlags, AFitIntoItsConfigurationsDirectoryIsRefusedBeforeWork) {
  const fs::path dir = FreshDirectory("fit_into_config");
  fs::create_directories(dir / "fd");
  fs::copy_file(fs::path(OWVAL_SHARED_DIR) / "reference/one_sprig/configuration",
                dir / "fd/configuration.txt");
  const std::string before = Bytes(dir / "fd/configuration.txt");
  const std::string command =
      "fit fd/configuration.txt --param elasticity_coefficient=1.62e8:log --target period=7e-4 "
      "--time 0.0002 -o fd";
  ExpectOneLineRefusal(OwvalIn(dir, command), "configuration.txt: is also an input", command);
  EXPECT_EQ(Bytes(dir / "fd/configuration.txt"), before);
  EXPECT_EQ(Entries(dir / "fd"), std::vector<std::string>{"configuration.txt"});
}

}  // namespace
}  // namespace owval::testing
