// owval compare A B with backend names, owval backends, owval bench backends: end to end on
// Sibernetic's recorded runs (../shared/reference as the store "opencl").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "owval/testing/test_files.hpp"

namespace owval::testing {
namespace {
namespace fs = std::filesystem;

const fs::path kReference = fs::path(OWVAL_SHARED_DIR) / "reference";

// A backends file in its own scratch folder: opencl = the reference store, plus `extra` entries.
fs::path BackendsFile(const std::string& name, const std::string& extra = "") {
  const fs::path dir = Scratch() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "backends.json") << R"({"backends": {"opencl": {"store": ")"
                                       << kReference.string() << "\"}" << extra << "}}\n";
  return dir / "backends.json";
}

std::string Flags(const fs::path& file) {
  return " --backends " + file.string() + " --cache " + (file.parent_path() / "cache").string();
}

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(BackendsCli, OwvalMatchesTheOpenclStoreAndSecondRunIsACacheHit) {
  if (ReferenceMissing(kReference / "one_sprig" / "configuration")) GTEST_SKIP();
  const fs::path file = BackendsFile("parity");
  const std::string command =
      "compare opencl owval --suite parity --scenarios one_sprig,test_gravity" + Flags(file);
  const Result first = Owval(command);
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  EXPECT_NE(first.out.find("all gates pass"), std::string::npos) << first.out;
  EXPECT_EQ(Count(first.out, "owval: ran"), 2u) << first.out;
  EXPECT_NE(first.out.find("one_sprig        frames"), std::string::npos) << first.out;
  const Result json = Owval(command + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto report = nlohmann::json::parse(json.out);
  for (const auto& s : report["scenarios"]) {
    EXPECT_EQ(s["runs"]["b"]["source"], "cache hit");
    // Every printed digit: zero distance and a zero frames gate.
    EXPECT_EQ(s["report"]["per_particle_distance_cu"]["mean"], 0.0) << s["scenario"];
    EXPECT_EQ(s["report"]["per_particle_distance_cu"]["final"], 0.0) << s["scenario"];
    for (const auto& g : s["report"]["gates"]) {
      if (g["name"] == "frames") {
        EXPECT_EQ(g["value"], 0.0) << s["scenario"];
      }
    }
  }
}

// Sibernetic's demos named by their path inside a checkout (scenarios/sibernetic/NAME.json):
// a checkout holding one_sprig and test_gravity at the repository's paths (the reference's
// copies, which carry the [simulation box] header Sibernetic's loader needs).
TEST(BackendsCli, SiberneticCheckoutDemosRunAgainstTheStore) {
  if (ReferenceMissing(kReference / "test_gravity" / "configuration")) GTEST_SKIP();
  const fs::path file = BackendsFile("checkout");
  const fs::path checkout = file.parent_path() / "sibernetic";
  fs::create_directories(checkout / "configuration" / "test" / "one");
  fs::copy_file(kReference / "one_sprig" / "configuration",
                checkout / "configuration" / "test" / "one_sprig_test");
  fs::copy_file(kReference / "test_gravity" / "configuration",
                checkout / "configuration" / "test" / "one" / "test_gravity");
  const Result all = Owval("compare opencl owval --sibernetic " + checkout.string() + Flags(file));
  ASSERT_EQ(all.exit_code, 0) << all.out << all.err;
  EXPECT_EQ(Count(all.out, "owval: ran"), 2u) << all.out;  // only the demos the checkout has
  EXPECT_NE(all.out.find("test_gravity"), std::string::npos) << all.out;
  EXPECT_NE(all.out.find("all gates pass"), std::string::npos) << all.out;
  const Result missing = Owval("compare opencl owval --scenarios demo2 --sibernetic " +
                               checkout.string() + Flags(file));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("configuration/demo2: not found (is "), std::string::npos)
      << missing.err;
  const Result unknown = Owval("compare opencl owval --scenarios demo9 --sibernetic " +
                               checkout.string() + Flags(file));
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("no Sibernetic demo \"demo9\""), std::string::npos) << unknown.err;
}

TEST(BackendsCli, OneByteOfConfigurationMissesTheCache) {
  if (ReferenceMissing(kReference / "test_gravity" / "configuration")) GTEST_SKIP();
  const fs::path file = BackendsFile("onebyte");
  const fs::path store = file.parent_path() / "store" / "test_gravity";
  fs::create_directories(store);
  fs::copy_file(kReference / "test_gravity" / "meta.json", store / "meta.json");
  fs::copy_file(kReference / "test_gravity" / "configuration", store / "configuration");
  const std::string command =
      "compare owval owval --reference-dir " + store.parent_path().string() + Flags(file);
  const Result first = Owval(command);
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  EXPECT_EQ(Count(first.out, "owval: ran"), 1u) << first.out;  // side b: a hit of side a's run
  EXPECT_EQ(Count(first.out, "owval: cache hit"), 1u) << first.out;
  EXPECT_EQ(Count(Owval(command).out, "owval: cache hit"), 2u);
  std::ofstream(store / "configuration", std::ios::app) << "\n";  // one more byte
  EXPECT_EQ(Count(Owval(command).out, "owval: ran"), 1u);
}

TEST(BackendsCli, PerturbedCommandBackendFailsNamingScenarioAndGate) {
  if (ReferenceMissing(kReference / "one_sprig" / "configuration")) GTEST_SKIP();
  const std::string stiff =
      R"(, "stiff": {"command": ")" + std::string(OWVAL_EXE) +
      R"( --quiet run {config} --time {time} --log-step {log_step} --out {out} --set elasticity_coefficient={set:k}", "set": {"k": "3.3e8"}, "layout": "opencl"})";
  const fs::path file = BackendsFile("perturbed", stiff);
  const Result r = Owval("compare opencl stiff --scenarios one_sprig" + Flags(file));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAILED: one_sprig: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("period"), std::string::npos) << r.out;
  // The same backend with the default stiffness passes: the failure is the perturbation.
  const Result same = Owval("compare opencl stiff --scenarios one_sprig --set k=3e8" + Flags(file));
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
}

// The store's test_gravity is Sibernetic's demo of that name: it is judged by
// scenarios/sibernetic/test_gravity.json (the liquid's centroid, `frames` at 0.015) as it is from
// a checkout. Judged on particle 0 with DD001's 5%, gravity 4% off passed (`frames` 0.038-0.040);
// 2% off measures 0.0195 / 0.0199, an integrator's difference (leapfrog) 0.0018.
TEST(BackendsCli, TheStoresDemosAreJudgedByTheirSiberneticManifests) {
  if (ReferenceMissing(kReference / "test_gravity" / "configuration")) GTEST_SKIP();
  const std::string heavier =
      R"(, "heavier": {"command": ")" + std::string(OWVAL_EXE) +
      R"( --quiet run {config} --time {time} --log-step {log_step} --out {out} --no-fields --set gravity_y={set:g}", "output": "{out}/trajectory.h5", "layout": "hdf5", "set": {"g": "-10.0"}})";
  const fs::path file = BackendsFile("demo_manifest", heavier);
  const Result r = Owval("compare opencl heavier --scenarios test_gravity --json" + Flags(file));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  const auto report = nlohmann::json::parse(r.out)["scenarios"][0]["report"];
  EXPECT_EQ(report["subject"], "liquid centroid y");
  const nlohmann::json* frames = GateNamed(report, "frames");
  ASSERT_NE(frames, nullptr) << report["gates"];
  EXPECT_EQ((*frames)["status"], "FAIL") << *frames;
  EXPECT_EQ((*frames)["threshold"], 0.015) << *frames;
  EXPECT_EQ((*frames)["threshold_source"], "manifest") << *frames;
  EXPECT_NEAR((*frames)["value"].get<double>(), 0.0195, 0.0005) << *frames;
  const Result one_percent =
      Owval("compare opencl heavier --scenarios test_gravity --set g=-9.9" + Flags(file));
  EXPECT_EQ(one_percent.exit_code, 0) << one_percent.out << one_percent.err;
}

// A store's run of a demo under a folder name of its own (demo1_1s, a 1 s run of
// configuration/demo1) is judged as that demo: meta.json's configuration.repo_path names the
// repository file, and the Sibernetic manifest naming the same file applies. Judged by folder name
// alone, it fell to particle 0 and DD001's defaults. A meta.json whose "configuration" is only a
// description keeps that fallback.
TEST(BackendsCli, AStoresDemoUnderAnotherNameIsJudgedByItsConfigurationsManifest) {
  if (ReferenceMissing(kReference / "test_gravity" / "configuration")) GTEST_SKIP();
  const fs::path store = Scratch() / "renamed_store";
  fs::remove_all(store);
  for (const char* folder : {"gravity_again", "gravity_described"}) {
    fs::create_directories(store / folder);
    for (const char* name : {"meta.json", "configuration", "position_buffer.txt"})
      fs::copy_file(kReference / "test_gravity" / name, store / folder / name);
  }
  nlohmann::json meta = nlohmann::json::parse(std::ifstream(kReference / "test_gravity/meta.json"));
  ASSERT_EQ(meta["configuration"]["repo_path"], "configuration/test/one/test_gravity");
  meta["configuration"] = "the repository's test_gravity, described in words only";
  fs::remove(store / "gravity_described" / "meta.json");
  std::ofstream(store / "gravity_described" / "meta.json") << meta.dump(1);
  const std::string heavier =
      R"(, "renamed": {"store": ")" + store.string() + R"("}, "heavier": {"command": ")" +
      std::string(OWVAL_EXE) +
      R"( --quiet run {config} --time {time} --log-step {log_step} --out {out} --no-fields --set gravity_y=-10.0", "output": "{out}/trajectory.h5", "layout": "hdf5"})";
  const fs::path file = BackendsFile("renamed_demo", heavier);
  const Result r = Owval("compare renamed heavier --json" + Flags(file));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  const auto scenarios = nlohmann::json::parse(r.out)["scenarios"];
  ASSERT_EQ(scenarios.size(), 2u) << r.out;
  const auto& again = scenarios[0]["report"];
  EXPECT_EQ(scenarios[0]["scenario"], "gravity_again");
  EXPECT_EQ(again["subject"], "liquid centroid y");
  const nlohmann::json* frames = GateNamed(again, "frames");
  ASSERT_NE(frames, nullptr) << again["gates"];
  EXPECT_EQ((*frames)["status"], "FAIL") << *frames;
  EXPECT_EQ((*frames)["threshold_source"], "manifest") << *frames;
  EXPECT_EQ(scenarios[1]["scenario"], "gravity_described");
  EXPECT_EQ(scenarios[1]["report"]["subject"], "particle 0 y");
}

// Two files, the reference a store folder's recorded run: the file form judges by its flags
// (DD001's defaults on particle 0 here, which owval with gravity 4% off passed on test_gravity),
// and says which manifest the named form judges that run by (under --quiet too, as render's
// notes: it is not progress). Not with --manifest, not for a copy of the file outside the store.
TEST(BackendsCli, TwoFilesFromTheStoreNameTheManifestTheNamedFormUses) {
  if (ReferenceMissing(kReference / "test_gravity" / "position_buffer.txt")) GTEST_SKIP();
  const std::string reference = (kReference / "test_gravity" / "position_buffer.txt").string();
  const std::string manifest =
      (fs::path(OWVAL_SOURCE_DIR) / "scenarios/sibernetic/test_gravity.json").string();
  const Result plain = Owval("compare " + reference + " " + reference);
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_NE(plain.err.find("owval: note: the reference is the store's run of test_gravity"),
            std::string::npos)
      << plain.err;
  EXPECT_NE(plain.err.find("add --manifest " + manifest + " to judge"), std::string::npos)
      << plain.err;
  EXPECT_EQ(Count(plain.err, "\n"), 1u) << plain.err;  // one line
  const Result given = Owval("compare " + reference + " " + reference + " --manifest " + manifest);
  EXPECT_EQ(given.exit_code, 0) << given.err;
  EXPECT_EQ(given.err.find("note:"), std::string::npos) << given.err;
  const fs::path copy = Scratch() / "outside_the_store.txt";
  fs::remove(copy);
  fs::copy_file(reference, copy);
  const Result outside = Owval("compare " + copy.string() + " " + reference);
  EXPECT_EQ(outside.exit_code, 0) << outside.err;
  EXPECT_EQ(outside.err.find("note:"), std::string::npos) << outside.err;
}

TEST(BackendsCli, FailingCommandIsExit2WithStderrTailAndEmptyCache) {
  if (ReferenceMissing(kReference / "one_sprig" / "configuration")) GTEST_SKIP();
  const fs::path file =
      BackendsFile("failing", R"(, "bad": {"command": "echo 'no device found' >&2; exit 4"})");
  const Result r = Owval("compare opencl bad --scenarios one_sprig" + Flags(file));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("backend bad: command failed, exit status 4"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no device found"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(file.parent_path() / "cache"));
  const Result truncated =
      Owval("compare opencl cut --scenarios one_sprig" +
            Flags(BackendsFile("truncated",
                               R"(, "cut": {"command": "head -c 100000 )" +
                                   (kReference / "one_sprig" / "position_buffer.txt").string() +
                                   R"( > {out}/position_buffer.txt"})")));
  EXPECT_EQ(truncated.exit_code, 2) << truncated.out;
  EXPECT_NE(truncated.err.find("backend cut: unreadable output"), std::string::npos)
      << truncated.err;
}

TEST(BackendsCli, UnknownNamesAreExit2ListingTheKnownOnes) {
  const fs::path file = BackendsFile("unknown");
  const Result r = Owval("compare opencl metal" + Flags(file));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown backend \"metal\"; known: owval, xpbd, wcsph, opencl"),
            std::string::npos)
      << r.err;
  const Result list = Owval("backends list --backends " + file.string());
  EXPECT_EQ(list.exit_code, 0);
  EXPECT_NE(list.out.find("opencl"), std::string::npos);
  const Result show = Owval("backends show pcisph --backends " + file.string());
  EXPECT_EQ(nlohmann::json::parse(show.out)["engine_backend"], "pcisph");
}

// `compare ref.h5 nosuch.h5` (or a directory as candidate) said `unknown backend "ref.h5"`,
// blaming the file that exists: the missing or unusable argument is named instead. Names without
// a '/' (in the working directory), as a user types them.
TEST(BackendsCli, AFileBesideAMissingFileOrADirectoryNamesTheOther) {
  const fs::path dir = Scratch() / "file_partner";
  fs::remove_all(dir);
  fs::create_directories(dir / "folder");
  fs::copy_file(owval::testing::kBundledOneSprig, dir / "ref.txt");
  for (const auto& [args, named] :
       std::vector<std::pair<std::string, std::string>>{{"ref.txt nosuch.h5", "nosuch.h5"},
                                                        {"nosuch.h5 ref.txt", "nosuch.h5"},
                                                        {"ref.txt folder", "folder"}}) {
    const Result r = RunCaptured("cd " + dir.string() + " && " + OWVAL_EXE + " --quiet compare " +
                                 args + " --cache " + (dir / "cache").string());
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.rfind("owval: error: " + named + ": ", 0), 0u) << args << ": " << r.err;
    EXPECT_EQ(r.err.find("unknown backend"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "cache"));
}

TEST(BackendsCli, BenchTimesEachBackendAsAProcess) {
  if (ReferenceMissing(kReference / "one_sprig" / "configuration")) GTEST_SKIP();
  const fs::path file = BackendsFile(
      "bench", R"(, "copy": {"command": "cp )" +
                   (kReference / "one_sprig" / "position_buffer.txt").string() + R"( {out}/"})");
  const Result r = Owval(
      "bench backends owval copy --scenario one_sprig --time 0.002 --repeat 2 "
      "--backends " +
      file.string() + " --markdown " + (file.parent_path() / "bench.md").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["backends"].size(), 2u);
  EXPECT_EQ(j["steps"], 100);
  EXPECT_EQ(j["backends"][0]["ratio_to_first"], 1.0);
  EXPECT_EQ(j["backends"][0]["wall_s"].size(), 2u);
  EXPECT_EQ(j["backends"][0]["cpu_s"].size(), 2u);
  EXPECT_GT(j["backends"][0]["median_cpu_s"].get<double>(), 0.0);  // owval ran 100 steps
  EXPECT_EQ(j["backends"][0]["cpu_ratio_to_first"], 1.0);
  EXPECT_GT(j["backends"][0]["peak_rss_kib"][0].get<long>(), 1000);
  EXPECT_NE(Slurp(file.parent_path() / "bench.md").find("| copy |"), std::string::npos);
  EXPECT_EQ(
      Owval("bench backends opencl --scenario one_sprig --backends " + file.string()).exit_code, 2);
}

// `--json` or `--markdown` naming the backends file or a file of the scenario it times would
// have replaced it with the report: refused before any run, the file kept.
TEST(BackendsCli, BenchRefusesAnOutputThatIsOneOfItsInputs) {
  if (ReferenceMissing(kReference / "one_sprig" / "configuration")) GTEST_SKIP();
  const fs::path file = BackendsFile("bench_inputs", "");
  const std::string before = Slurp(file);
  const fs::path store = file.parent_path() / "store", meta = store / "one_sprig" / "meta.json";
  fs::create_directories(store / "one_sprig");  // a copy: the test must not risk ../shared
  for (const char* name : {"configuration", "meta.json"})
    fs::copy_file(kReference / "one_sprig" / name, store / "one_sprig" / name);
  const std::string meta_before = Slurp(meta);
  for (const std::string& flags :
       {"--json " + file.string(), "--markdown " + file.string(),
        "--reference-dir " + store.string() + " --json " + meta.string()}) {
    const Result r = Owval("bench backends owval --scenario one_sprig --time 0.002 --backends " +
                           file.string() + " " + flags);
    EXPECT_EQ(r.exit_code, 2) << flags;
    EXPECT_NE(r.err.find("is also an input of this command"), std::string::npos) << r.err;
  }
  EXPECT_EQ(Slurp(file), before);
  EXPECT_EQ(Slurp(meta), meta_before);
}

TEST(BackendsCli, BenchRunsTheBackendsRoundByRound) {
  // Two command backends that log their runs: with --repeat 2 the order must be a b a b, so that
  // a drift in the machine's speed falls on both alike.
  if (ReferenceMissing(kReference / "one_sprig" / "configuration")) GTEST_SKIP();
  const fs::path log = Scratch() / "bench_order.log";
  fs::remove(log);
  const std::string copy = "cp " + (kReference / "one_sprig" / "position_buffer.txt").string();
  const auto entry = [&](const std::string& name) {
    return ", \"" + name + "\": {\"command\": \"echo " + name + " >> " + log.string() + " && " +
           copy + " {out}/\"}";
  };
  const fs::path file = BackendsFile("bench_order", entry("a") + entry("b"));
  const Result r = Owval(
      "bench backends a b --scenario one_sprig --time 0.002 --repeat 2 "
      "--backends " +
      file.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Slurp(log), "a\nb\na\nb\n");
}

}  // namespace
}  // namespace owval::testing
