// Template quoting (through a real shell), registry precedence, cache keys and commits, scenario
// folders, and a failing command that leaves nothing in the cache.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "owval/backends/bench.hpp"
#include "owval/backends/cache.hpp"
#include "owval/backends/process.hpp"
#include "owval/backends/registry.hpp"
#include "owval/backends/runner.hpp"
#include "owval/backends/scenario_store.hpp"
#include "owval/backends/sha256.hpp"
#include "owval/base/command_template.hpp"
#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval::backends {
namespace {
namespace fs = std::filesystem;

fs::path Scratch(const std::string& name) { return owval::testing::TestScratch(name); }

void Write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string Read(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(Sha256, MatchesFips180Vectors) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Template, QuotesEachValueForTheShell) {
  EXPECT_EQ(ShellQuote("a b"), "'a b'");
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellQuote(""), "''");
  TemplateValues v;
  v.values["config"] = "/tmp/dir with space/it's \"q\" $HOME `x`";
  const std::string command = ExpandTemplate("printf '%s\\n' {config}", v, true, "test");
  const fs::path dir = Scratch("quote");
  ProcessOptions p;
  p.command = command;
  p.stdout_path = dir / "out.txt";
  ASSERT_TRUE(RunShellCommand(p).ok());
  EXPECT_EQ(Read(dir / "out.txt"), v.values["config"] + "\n");  // one argument, unexpanded
}

TEST(Process, MeasuresTheChildsCpuTimeApartFromItsWallTime) {
  ProcessOptions busy;  // about 0.2 s of work in the shell itself
  busy.command = "i=0; while [ $i -lt 300000 ]; do i=$((i+1)); done";
  const ProcessResult b = RunShellCommand(busy);
  ASSERT_TRUE(b.ok());
  EXPECT_GT(b.cpu_s, 0.02);
  EXPECT_LT(b.cpu_s, b.wall_s * 1.5);  // one thread: no more CPU than wall time, give or take
  ProcessOptions idle;                 // waits without working
  idle.command = "sleep 0.3";
  const ProcessResult s = RunShellCommand(idle);
  ASSERT_TRUE(s.ok());
  EXPECT_GE(s.wall_s, 0.3);
  EXPECT_LT(s.cpu_s, 0.1);
}

TEST(Bench, BuiltInRunsTakeOneThreadCountWhateverTheLoad) {
  Backend owval;
  owval.name = "xpbd", owval.engine_backend = "xpbd";
  BenchOptions o;
  o.scenario.configuration = "/c", o.scenario.time_s = 0.1, o.scenario.log_step = 20;
  o.owval_executable = "/bin/owval";
  const std::string all = " --threads " + std::to_string(std::thread::hardware_concurrency());
  EXPECT_NE(BenchCommand(owval, o, "/o").find(all), std::string::npos);
  o.threads = 3;
  EXPECT_NE(BenchCommand(owval, o, "/o").find(" --threads 3"), std::string::npos);
}

TEST(Template, ExpandsSetsAndRejectsUnknownPlaceholders) {
  TemplateValues v;
  v.values = {{"time", "0.05"}};
  v.sets = {{"k", "3e8"}};
  EXPECT_EQ(ExpandTemplate("t={time} k={set:k}", v, false, "w"), "t=0.05 k=3e8");
  EXPECT_THROW(ExpandTemplate("{nope}", v, false, "w"), InputError);
  EXPECT_THROW(ExpandTemplate("{set:missing}", v, false, "w"), InputError);
  EXPECT_THROW(ExpandTemplate("{time", v, false, "w"), InputError);
}

TEST(Registry, PrecedenceFlagThenCurrentDirectoryThenXdg) {
  const fs::path dir = Scratch("registry");
  fs::create_directories(dir / "cwd");
  fs::create_directories(dir / "xdg" / "owval");
  Write(dir / "flag.json", R"({"backends": {"from_flag": {"store": "s"}}})");
  Write(dir / "cwd" / "owval-backends.json", R"({"backends": {"from_cwd": {"store": "s"}}})");
  Write(dir / "xdg" / "owval" / "backends.json", R"({"backends": {"from_xdg": {"store": "s"}}})");
  RegistryOptions o;
  o.file = dir / "flag.json";
  o.current_directory = dir / "cwd";
  o.xdg_config_home = (dir / "xdg").string();
  o.home = "/nonexistent";
  EXPECT_EQ(LoadRegistry(o).Names().back(), "from_flag");
  o.file.clear();
  EXPECT_EQ(LoadRegistry(o).Names().back(), "from_cwd");
  fs::remove(dir / "cwd" / "owval-backends.json");
  const Registry xdg = LoadRegistry(o);
  EXPECT_EQ(xdg.Names().back(), "from_xdg");
  EXPECT_EQ(xdg.Find("from_xdg").store, dir / "xdg" / "owval" / "s");  // relative to the file
  fs::remove(dir / "xdg" / "owval" / "backends.json");
  EXPECT_EQ(LoadRegistry(o).Names(), (std::vector<std::string>{"owval", "xpbd", "wcsph"}));
  o.file = dir / "missing.json";
  EXPECT_THROW(LoadRegistry(o), InputError);
}

// `backends list --backends X` said "X: no such file" for a directory and an empty file too:
// each is named with what --backends expects.
TEST(Registry, ABackendsFlagThatIsNoBackendsFileSaysWhatWasExpected) {
  const fs::path dir = Scratch("registry_flag");
  fs::create_directories(dir / "folder");
  Write(dir / "empty.json", "");
  Write(dir / "list.json", "[1, 2]");
  const std::string expected = "expected a backends file (JSON: docs/backends.md)";
  for (const auto& [name, message] : std::vector<std::pair<std::string, std::string>>{
           {"missing.json", "cannot open file (missing), " + expected},
           {"folder", "is a directory, " + expected},
           {"empty.json", "is empty; expected a JSON document"},
           {"list.json", "expected {\"backends\": {NAME: {...}}}"}}) {
    RegistryOptions o;
    o.file = dir / name;
    try {
      LoadRegistry(o);
      ADD_FAILURE() << name;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), (dir / name).string() + ": " + message);
    }
  }
}

TEST(Registry, FindsAliasesAndNamesTheKnownOnes) {
  const Registry r = ParseRegistry(
      nlohmann::json::parse(R"({"backends": {"opencl": {"command": "./S -f {config}"}}})"),
      "/x/b.json", "/home/u");
  EXPECT_EQ(r.Find("pcisph").name, "owval");
  EXPECT_EQ(r.Find("opencl").kind, BackendKind::kCommand);
  try {
    r.Find("metal");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("owval, xpbd, wcsph, opencl"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ParseRegistry(nlohmann::json::parse(R"({"backends": {"owval": {"store": "s"}}})"),
                             "b.json", ""),
               InputError);
  EXPECT_THROW(ParseRegistry(nlohmann::json::parse(R"({"backends": {"x": {"layout": "csv",
                             "store": "s"}}})"),
                             "b.json", ""),
               InputError);
}

TEST(Cache, KeyChangesWithEveryInput) {
  const std::string key = RunKey("cmd", "config", 0.05, 2e-5, 1);
  EXPECT_EQ(key.size(), 64u);
  EXPECT_EQ(key, RunKey("cmd", "config", 0.05, 2e-5, 1));
  EXPECT_NE(key, RunKey("cmd2", "config", 0.05, 2e-5, 1));
  EXPECT_NE(key, RunKey("cmd", "confih", 0.05, 2e-5, 1));  // one byte
  EXPECT_NE(key, RunKey("cmd", "config", 0.0500001, 2e-5, 1));
  EXPECT_NE(key, RunKey("cmd", "config", 0.05, 1e-5, 1));
  EXPECT_NE(key, RunKey("cmd", "config", 0.05, 2e-5, 2));
}

TEST(Cache, OnlyCommittedRunsAreFound) {
  const fs::path dir = Scratch("cache");
  const RunCache cache(CacheOptions{dir, true});
  const std::string key(64, 'a');
  const fs::path temporary = cache.Begin(key);
  Write(temporary / "x", "1");
  EXPECT_FALSE(cache.Find(key));
  EXPECT_EQ(cache.Commit(temporary, key), dir / key);
  EXPECT_EQ(*cache.Find(key), dir / key);
  EXPECT_FALSE(fs::exists(temporary));
}

TEST(Process, LogTailIsOnePrintableLine) {
  const fs::path dir = Scratch("tail");
  Write(dir / "err", "1\n2\n\n3\n4\n5\n6\x01\tend\n");
  EXPECT_EQ(LogTail(dir / "err"), "2 | 3 | 4 | 5 | 6? end");
  EXPECT_EQ(LogTail(dir / "err", 5, 10), "... 6? end");
  EXPECT_EQ(LogTail(dir / "missing"), "");
}

TEST(ScenarioStore, ReadsTheReferenceFolders) {
  const fs::path root = fs::path(OWVAL_SHARED_DIR) / "reference";
  if (!fs::exists(root / "one_sprig" / "meta.json")) GTEST_SKIP() << "no shared reference";
  const auto found = FindScenarios(root, {"one_sprig", "test_gravity", "demo1"});
  EXPECT_DOUBLE_EQ(found[0].time_s, 0.05);
  EXPECT_EQ(found[0].log_step, 1);
  EXPECT_DOUBLE_EQ(found[1].time_s, 0.05);
  EXPECT_EQ(found[1].log_step, 5);
  EXPECT_DOUBLE_EQ(found[2].time_s, 0.2);
  EXPECT_EQ(found[2].log_step, 20);
  EXPECT_THROW(FindScenarios(root, {"demo1_density_diag"}), InputError);  // no configuration
  for (const Scenario& s : FindScenarios(root, {})) EXPECT_FALSE(s.configuration.empty());
}

// A scenario folder's meta.json from another hand: "log_step": 1e300 became INT_MIN through
// static_cast<int> (the run then said "--log-step: expected a number > 0, found '-2147483648'",
// and compare ran with it, exit 0), and the recorded command's "timelimit=." or "timelimit=1e999"
// ended the command with std::stod's whole message, "stod".
TEST(ScenarioStore, MetaNumbersOutOfRangeNameTheFileAndField) {
  const fs::path dir = Scratch("meta_numbers") / "one";
  fs::create_directories(dir);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"time_step_s": 2e-5, "log_step": 1e300, "frames": 10})", "log_step from 1 to 2^31-1"},
      {R"({"time_step_s": 2e-5, "log_step": 2147483648, "frames": 10})",
       "log_step from 1 to 2^31-1"},
      {R"({"time_step_s": 2e-5, "log_step": 1, "command": "x timelimit=."})",
       "\"command\": timelimit=.: expected a positive finite number"},
      {R"({"time_step_s": 2e-5, "log_step": 1, "command": "x timelimit=1e999"})",
       "\"command\": timelimit=1e999: expected a positive finite number"},
      {R"({"time_step_s": 1e300, "log_step": 1, "frames": 1e300})",
       "time: expected a positive finite number of seconds"},
      // The repository path keys the Sibernetic manifest the run is judged by (suite.hpp).
      {R"({"time_step_s": 2e-5, "log_step": 1, "frames": 1, "configuration": {"repo_path": 7}})",
       "\"configuration.repo_path\": expected a path string"}};
  for (const auto& [meta, says] : cases) {
    Write(dir / "meta.json", meta);
    try {
      ReadScenario(dir);
      ADD_FAILURE() << meta << " was read";
    } catch (const InputError& e) {
      const std::string line = e.what();
      EXPECT_NE(line.find("meta.json"), std::string::npos) << line;
      EXPECT_NE(line.find(says), std::string::npos) << meta << ": " << line;
    }
  }
  Write(dir / "meta.json", R"({"time_step_s": 2e-5, "log_step": 7, "command": "timelimit=0.5"})");
  EXPECT_EQ(ReadScenario(dir).log_step, 7);
  EXPECT_DOUBLE_EQ(ReadScenario(dir).time_s, 0.5);
  EXPECT_EQ(ReadScenario(dir).sibernetic_configuration, "");
  Write(dir / "meta.json", R"({"time_step_s": 2e-5, "log_step": 1, "frames": 1, )"
                           R"("configuration": {"repo_path": "configuration/demo1"}})");
  EXPECT_EQ(ReadScenario(dir).sibernetic_configuration, "configuration/demo1");
}

Scenario TinyScenario(const fs::path& dir) {
  Write(dir / "configuration", "[simulation box]\n0\n1\n0\n1\n0\n1\n[end]\n");
  Scenario s;
  s.name = "tiny";
  s.directory = dir;
  s.configuration = dir / "configuration";
  s.time_s = 0.01;
  return s;
}

TEST(Runner, FailingCommandNamesBackendAndStderrAndCachesNothing) {
  const fs::path dir = Scratch("failing");
  const fs::path cache_dir = dir / "cache";
  const RunCache cache(CacheOptions{cache_dir, true});
  Backend b;
  b.name = "broken";
  b.kind = BackendKind::kCommand;
  b.command = "echo first >&2; echo 'disk on fire' >&2; exit 3";
  RunRequest request;
  request.scenario = TinyScenario(dir);
  try {
    ObtainRun(b, request, cache);
    FAIL();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("backend broken"), std::string::npos) << what;
    EXPECT_NE(what.find("exit status 3"), std::string::npos) << what;
    EXPECT_NE(what.find("first | disk on fire"), std::string::npos) << what;
    EXPECT_LE(what.size(), 300u);
  }
  b.command = "true";  // writes nothing
  EXPECT_THROW(ObtainRun(b, request, cache), InputError);
  b.command = "printf '0\\n1\\n' > {out}/position_buffer.txt";  // truncated header
  EXPECT_THROW(ObtainRun(b, request, cache), InputError);
  EXPECT_TRUE(fs::is_empty(cache_dir));
}

TEST(Runner, CommandWritingIntoOutRunsWithARelativeCacheAndAnotherWorkingDirectory) {
  const fs::path root = fs::path(OWVAL_SHARED_DIR) / "reference";
  const fs::path recorded = root / "one_sprig" / "position_buffer.txt";
  if (!fs::exists(recorded)) GTEST_SKIP() << "no reference";
  const fs::path dir = Scratch("relative_cache");
  fs::create_directories(dir / "elsewhere");
  const fs::path previous = fs::current_path();
  fs::current_path(dir);
  Backend b;
  b.name = "copyref";
  b.kind = BackendKind::kCommand;
  b.command = "cp " + recorded.string() + " {out}/position_buffer.txt";
  b.working_directory = dir / "elsewhere";
  RunRequest request;
  request.scenario = ReadScenario(root / "one_sprig");
  const RunCache cache(CacheOptions{"cache", true});  // relative, as `--cache cache2`
  RunOutcome ran, hit;
  try {
    ran = ObtainRun(b, request, cache);
    hit = ObtainRun(b, request, cache);
  } catch (...) {
    fs::current_path(previous);
    throw;
  }
  fs::current_path(previous);
  EXPECT_EQ(ran.source, "ran");
  EXPECT_EQ(hit.source, "cache hit");
  EXPECT_EQ(ran.Frames()->frame_count(), hit.Frames()->frame_count());
  EXPECT_GT(ran.Frames()->frame_count(), 0u);
  EXPECT_TRUE(fs::is_empty(dir / "elsewhere"));
}

// With the cache off, a run's directory is scratch: it lives as long as an outcome that reads it.
TEST(Runner, AnUncachedRunIsReadableUntilItsLastOutcomeGoes) {
  const fs::path root = fs::path(OWVAL_SHARED_DIR) / "reference";
  const fs::path recorded = root / "one_sprig" / "position_buffer.txt";
  if (!fs::exists(recorded)) GTEST_SKIP() << "no reference";
  Backend b;
  b.name = "copyref";
  b.kind = BackendKind::kCommand;
  b.command = "cp " + recorded.string() + " {out}/position_buffer.txt";
  RunRequest request;
  request.scenario = ReadScenario(root / "one_sprig");
  fs::path file;
  {
    RunOutcome copy;
    {
      const RunOutcome o = ObtainRun(b, request, RunCache(CacheOptions{"", false}));
      EXPECT_EQ(o.source, "ran");
      file = o.file;
      EXPECT_TRUE(file.is_absolute()) << file;
      copy = o;
    }
    EXPECT_EQ(copy.Frames()->frame_count(), 2500u);
  }
  EXPECT_FALSE(fs::exists(file)) << file;
}

TEST(Runner, CommandWithoutItsProgramFallsBackToTheStore) {
  const fs::path root = fs::path(OWVAL_SHARED_DIR) / "reference";
  if (!fs::exists(root / "test_gravity" / "position_buffer.txt")) GTEST_SKIP() << "no reference";
  Backend b;
  b.name = "opencl";
  b.kind = BackendKind::kCommand;
  b.command = "./Sibernetic -no_g -f {config}";
  b.working_directory = "/nonexistent";
  b.store = root;
  EXPECT_FALSE(ProgramAvailable(b));
  RunRequest request;
  request.scenario = ReadScenario(root / "test_gravity");
  const RunOutcome o = ObtainRun(b, request, RunCache(CacheOptions{"", false}));
  EXPECT_EQ(o.source, "store");
  EXPECT_NE(o.detail.find("fallback"), std::string::npos);
  EXPECT_EQ(o.Frames()->frame_count(), 500u);
}

}  // namespace
}  // namespace owval::backends
