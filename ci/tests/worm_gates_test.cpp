// The worm's gates on Sibernetic's 0.6 s worm run, used as both reference and candidate.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "owval/ci/checklist.hpp"
#include "owval/ci/gates.hpp"
#include "owval/engine/muscles.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/muscle_log.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/worm_formats.hpp"
#include "worm_gates.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

const fs::path kWorm =
    fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";

fs::path WormDirectory() {
  const fs::path dir = owval::testing::TestScratch("worm");
  fs::create_symlink(kWorm, dir / "reference.txt.gz");
  fs::create_symlink(kWorm, dir / "candidate.txt.gz");
  return dir;
}

const GateResult* Find(const GateReport& r, const std::string& name) {
  for (const GateResult& g : r.gates)
    if (g.name == name) return &g;
  return nullptr;
}

TEST(WormGates, QuickTestRequiresAWconForWormRuns) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const fs::path dir = WormDirectory();
  const GateReport without = QuickTest(dir);
  const GateResult* g = Find(without, "worm run wrote a WCON");
  ASSERT_TRUE(g);
  EXPECT_FALSE(g->pass);
  EXPECT_FALSE(without.pass());
  TextReadOptions quiet;
  quiet.quiet = true;
  WriteWcon(kinematics::TrackFromTrajectory(ReadTrajectory(kWorm, quiet)), dir / "worm.wcon");
  const GateReport with = QuickTest(dir);
  EXPECT_TRUE(with.pass()) << with.ToText();
  EXPECT_EQ(Find(with, "worm run wrote a WCON")->detail,
            "worm.wcon: 200 time points, 99 midline points");
  // Cut short after a line: the one parse refuses it, and both gates that read it say where the
  // file ends (the line after the last, column 1).
  const std::string text = testing::FileBytes(dir / "worm.wcon");
  const std::size_t cut = text.find('\n', text.size() / 2) + 1;
  std::ofstream(dir / "worm.wcon", std::ios::binary | std::ios::trunc) << text.substr(0, cut);
  const std::string line = std::to_string(1 + std::count(text.begin(), text.begin() + cut, '\n'));
  const GateReport cut_short = QuickTest(dir);
  EXPECT_FALSE(cut_short.pass());
  for (const char* gate : {"worm run wrote a WCON", "worm.wcon describes the candidate"}) {
    ASSERT_TRUE(Find(cut_short, gate)) << gate;
    EXPECT_FALSE(Find(cut_short, gate)->pass);
    EXPECT_EQ(
        Find(cut_short, gate)
            ->detail.rfind((dir / "worm.wcon").string() + ":" + line + ":1: not valid JSON: ", 0),
        0u)
        << Find(cut_short, gate)->detail;
  }
  fs::remove_all(dir);
}

// The 0.6 s reference holds about one undulation: its bend angle crosses zero fewer than three
// times, so no frequency is accepted and the Tier-3 gate fails on it (an honest result, not a
// tolerance to loosen). The metrics and ranges are printed either way.
TEST(WormGates, ValidatePrintsEachTier3MetricWithItsBaselineRange) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const fs::path dir = WormDirectory();
  const GateReport r = Validate(dir);
  std::printf("%s", r.ToText().c_str());
  for (const char* metric : {"speed", "frequency", "wavelength"}) {
    const GateResult* g = Find(r, std::string("Tier-3 ") + metric);
    ASSERT_TRUE(g) << metric;
    EXPECT_NE(g->detail.find("baseline (crawling)"), std::string::npos) << g->detail;
    EXPECT_TRUE(Find(r, std::string("kinematics parity ") + metric)->pass);
  }
  EXPECT_FALSE(Find(r, "Tier-3 frequency")->pass);
  EXPECT_NE(Find(r, "Tier-3 frequency")->detail.find("fewer than 3 zero crossings"),
            std::string::npos);
  EXPECT_FALSE(r.pass());
  fs::remove_all(dir);
}

Trajectory ReadWorm() {
  TextReadOptions quiet;
  quiet.quiet = true;
  return ReadTrajectory(kWorm, quiet);
}

// The run's first `frames` frames, every one replaced by frame 0 when `frozen`, or in reverse
// order at the run's own times when `reversed`.
Trajectory Edited(const Trajectory& run, std::size_t frames, bool frozen, bool reversed) {
  Trajectory t = run;
  const std::size_t n = run.particle_count() * 3;
  t.time_s.resize(frames);
  t.positions.resize(frames * n);
  for (std::size_t f = 0; f < frames; ++f) {
    const std::size_t from = frozen ? 0 : reversed ? frames - 1 - f : f;
    std::copy_n(run.positions.begin() + long(from * n), n, t.positions.begin() + long(f * n));
  }
  t.velocities.clear(), t.density.clear(), t.pressure.clear();
  return t;
}

// A worm that does not move (frame 0 repeated) beside the WCON, midline log and Zarr store of the
// run it copies: quick-test passed it (the WCON was readable); the side files now have to describe
// the candidate's particles. The first 20 frames keep the test short.
// The run's first 20 frames as reference.h5 and frame 0 repeated 20 times as candidate.h5, in a
// new scratch directory `name`.
struct FrozenWormDirectory {
  explicit FrozenWormDirectory(const char* name)
      : reference(Edited(ReadWorm(), 20, false, false)),
        frozen(Edited(reference, 20, true, false)),
        dir(owval::testing::TestScratch(name)) {
    WriteHdf5(reference, dir / "reference.h5");
    WriteHdf5(frozen, dir / "candidate.h5");
  }
  const Trajectory reference, frozen;
  const fs::path dir;
};

TEST(WormGates, QuickTestFailsSideFilesThatDescribeAnotherRun) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const FrozenWormDirectory worm("worm_side");
  const Trajectory &reference = worm.reference, &frozen = worm.frozen;
  const fs::path& dir = worm.dir;
  WriteWcon(kinematics::TrackFromTrajectory(reference), dir / "worm.wcon");
  kinematics::WriteWormMotionLog(reference, dir / "worm_motion_log.txt");
  WriteOmeZarr(reference, dir / "trajectory.zarr");
  const GateReport copied = QuickTest(dir);
  EXPECT_FALSE(copied.pass()) << copied.ToText();
  ASSERT_TRUE(Find(copied, "worm.wcon describes the candidate"));
  EXPECT_EQ(Find(copied, "worm.wcon describes the candidate")
                ->detail.rfind("20 time points; 19 disagree", 0),
            0u);
  EXPECT_FALSE(Find(copied, "worm_motion_log.txt describes the candidate")->pass);
  EXPECT_FALSE(Find(copied, "trajectory.zarr describes the candidate")->pass);
  EXPECT_TRUE(Find(copied, "worm run wrote a WCON")->pass);
  WriteWcon(kinematics::TrackFromTrajectory(frozen), dir / "worm.wcon");
  kinematics::WriteWormMotionLog(frozen, dir / "worm_motion_log.txt");
  fs::remove_all(dir / "trajectory.zarr");
  WriteOmeZarr(frozen, dir / "trajectory.zarr");
  const GateReport own = QuickTest(dir);
  EXPECT_TRUE(Find(own, "trajectory.zarr describes the candidate")->pass);
  EXPECT_TRUE(own.pass()) << own.ToText();
  fs::remove_all(dir);
}

// A WCON whose skeleton is the candidate's but whose centroid (cx, cy) is another run's: the
// centroid was not compared and the WCON passed. Its own WCON, written by owval, still passes.
TEST(WormGates, QuickTestFailsAWconWhoseCentroidIsAnotherRuns) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const FrozenWormDirectory worm("worm_centroid");
  const Trajectory &reference = worm.reference, &frozen = worm.frozen;
  const fs::path& dir = worm.dir;
  WormTrack track = kinematics::TrackFromTrajectory(frozen);
  const WormTrack moving = kinematics::TrackFromTrajectory(reference);
  track.cx_mm = moving.cx_mm;  // the points right, the centroid the moving run's
  track.cy_mm = moving.cy_mm;
  WriteWcon(track, dir / "worm.wcon");
  const GateReport wrong = QuickTest(dir);
  EXPECT_FALSE(wrong.pass());
  const GateResult* gate = Find(wrong, "worm.wcon describes the candidate");
  ASSERT_TRUE(gate);
  EXPECT_FALSE(gate->pass);
  EXPECT_EQ(gate->detail.rfind("20 time points; 19 disagree with the trajectory's skeleton and "
                               "centroid; worst ",
                               0),
            0u)
      << gate->detail;
  EXPECT_NE(gate->detail.find(", centroid ("), std::string::npos) << gate->detail;
  EXPECT_EQ(gate->detail.find('\n'), std::string::npos);
  WriteWcon(kinematics::TrackFromTrajectory(frozen), dir / "worm.wcon");
  const GateReport own = QuickTest(dir);
  EXPECT_TRUE(own.pass()) << own.ToText();
  fs::remove_all(dir);
}

// The PR checklist holds a worm candidate's side files to it as quick-test does (item 3, which
// makes the directory unreviewable): a frozen worm beside the reference's WCON was a readable
// candidate. Without side files, or with its own, item 3 passes on the trajectory alone.
TEST(WormGates, ChecklistItemThreeFailsSideFilesThatDescribeAnotherRun) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const FrozenWormDirectory worm("worm_checklist");
  const Trajectory &reference = worm.reference, &frozen = worm.frozen;
  const fs::path& dir = worm.dir;
  const auto item_three = [&] { return RunChecklist(dir).items.at(2); };
  const ChecklistItem bare = item_three();
  EXPECT_TRUE(bare.pass) << bare.detail;
  WriteWcon(kinematics::TrackFromTrajectory(reference), dir / "worm.wcon");
  const ChecklistItem copied = item_three();
  EXPECT_FALSE(copied.pass);
  EXPECT_NE(copied.detail.find("FAILS worm.wcon describes the candidate"), std::string::npos)
      << copied.detail;
  WriteWcon(kinematics::TrackFromTrajectory(frozen), dir / "worm.wcon");
  const ChecklistItem own = item_three();
  EXPECT_TRUE(own.pass) << own.detail;
  EXPECT_NE(own.detail.find("1 worm side file(s) describe it"), std::string::npos) << own.detail;
  fs::remove_all(dir);
}

// The reference's frames in reverse order: the worm goes backwards at the reference's pace, with
// its frequency and wavelength. The speed parity compared magnitudes ("0.08322, 0.08322: 0.00%
// apart") and Tier-3 printed 0.08322 mm/s; both now see the direction.
TEST(WormGates, ValidateFailsAWormGoingBackwards) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  const fs::path dir = owval::testing::TestScratch("worm_backwards");
  fs::create_symlink(kWorm, dir / "reference.txt.gz");
  const Trajectory run = ReadWorm();
  WriteHdf5(Edited(run, run.frame_count(), false, true), dir / "candidate.h5");
  const GateReport r = Validate(dir, {}, kWorm);
  EXPECT_EQ(Find(r, "kinematics parity speed")->detail,
            "reference 0.08322, candidate -0.08322: 200.00% apart (max 5%)");
  EXPECT_FALSE(Find(r, "kinematics parity speed")->pass);
  EXPECT_EQ(Find(r, "Tier-3 speed")->detail.rfind("-0.08322 mm/s (backwards)", 0), 0u)
      << Find(r, "Tier-3 speed")->detail;
  EXPECT_TRUE(Find(r, "kinematics parity wavelength")->pass);
  fs::remove_all(dir);
}

const fs::path kWormRun = fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s";

// Sibernetic's muscles_activity_buffer.txt is owval's MuscleSimulationSignal, to the printed
// digits. The mapping, from Sibernetic's source (owPhysicsFluidSimulator::simulationStep, commit
// 8d2df73, the reference's): iteration k runs its physics, then calls
// MuscleSimulation.run(), whose step counter is k at that call (it starts at 0 and adds its
// increment, 1.0, after each call), then logs the 96 values when k % log_step == 0, then uploads
// them for iteration k+1. So line j is iteration k = j·log_step's, and it holds run()'s call
// number k: MuscleSimulationSignal(j·log_step). The run's log_step is 150 (meta.json: 30,000
// steps of 2e-5 s, 200 lines).
TEST(MuscleLogParity, SiberneticsActivationsAreOwvalsSignalToThePrintedDigits) {
  const fs::path log = kWormRun / "muscles_activity_buffer.txt";
  if (!fs::exists(log)) {
    if (std::getenv("OWVAL_REQUIRE_REFERENCE")) FAIL() << "no " << log;
    GTEST_SKIP() << "no " << log;
  }
  const int log_step =
      nlohmann::json::parse(testing::FileBytes(kWormRun / "meta.json")).at("log_step").get<int>();
  ASSERT_EQ(log_step, 150);
  std::ifstream lines(log);
  std::string line;
  std::size_t j = 0, differing = 0;
  while (std::getline(lines, line)) {
    const double call = double(j) * log_step;
    const std::string owval = kinematics::FormatMuscleLogLine(engine::MuscleSimulationSignal(call));
    if (line + "\n" != owval && differing++ < 3)
      ADD_FAILURE() << "line " << j + 1 << " (call " << call << ")\n  Sibernetic: " << line
                    << "\n  owval:      " << owval;
    ++j;
  }
  EXPECT_EQ(j, 200u);
  EXPECT_EQ(differing, 0u) << "lines whose printed activations differ";
  // The reader takes the same file: 200 lines of 96 values, the largest 0.575's float.
  kinematics::MuscleLogReader reader(log);
  kinematics::PrintedActivations values{};
  double largest = 0;
  std::size_t read = 0;
  while (reader.Next(&values)) {
    ++read;
    largest = std::max(largest, *std::max_element(values.begin(), values.end()));
  }
  EXPECT_EQ(read, 200u);
  EXPECT_EQ(largest, 0.5749999);
}

const GateResult* FindGate(const std::vector<GateResult>& gates, const std::string& name) {
  for (const GateResult& g : gates)
    if (g.name == name) return &g;
  return nullptr;
}

// A candidate directory's muscles_activity_buffer.txt is held to owval's signal at the
// candidate's logged steps: Sibernetic's own file beside its own run passes; a value moved by two
// units of its 7th digit, the lines shifted by one, and zeros beside a worm fail.
TEST(WormGates, SideFilesHoldTheMuscleLogToOwvalsSignal) {
  const fs::path log = kWormRun / "muscles_activity_buffer.txt";
  if (!fs::exists(kWorm) || !fs::exists(log)) GTEST_SKIP() << "no " << kWormRun;
  const fs::path dir = owval::testing::TestScratch("worm_muscles");
  fs::create_symlink(kWorm, dir / "candidate.txt.gz");
  const std::string name = "muscles_activity_buffer.txt holds owval's muscle signal";
  const auto gate = [&](const std::string& text) {
    std::ofstream(dir / "muscles_activity_buffer.txt", std::ios::binary | std::ios::trunc) << text;
    const std::vector<GateResult> gates =
        internal::WormSideFileGates(dir, dir / "candidate.txt.gz");
    EXPECT_EQ(gates.size(), 1u);
    const GateResult* g = FindGate(gates, name);
    return g ? *g : GateResult{name, false, "no such gate"};
  };
  const std::string own = testing::FileBytes(log);
  const GateResult passes = gate(own);
  EXPECT_TRUE(passes.pass) << passes.detail;
  EXPECT_EQ(
      passes.detail.rfind("200 lines; 0 disagree with owval's muscle signal at their steps", 0), 0u)
      << passes.detail;
  // Line 101 (step 15,000), muscle 1 (8.723249e-02): its 7th significant digit moved by two.
  std::string edited = own;
  std::size_t at = 0;
  for (int i = 0; i < 100; ++i) at = edited.find('\n', at) + 1;
  ASSERT_NE(edited[at], '0') << "a non-zero value: " << edited.substr(at, 12);
  char& digit = edited[at + 7];
  digit = digit < '8' ? char(digit + 2) : char(digit - 2);
  const GateResult moved = gate(edited);
  EXPECT_FALSE(moved.pass);
  EXPECT_EQ(moved.detail.rfind("200 lines; 1 disagree", 0), 0u) << moved.detail;
  EXPECT_NE(moved.detail.find("at line 101 (step 15000), muscle 1: "), std::string::npos)
      << moved.detail;
  // Shifted by one: line j holds line j+1's values, the last line repeated.
  std::string shifted = own.substr(own.find('\n') + 1);
  shifted += own.substr(own.rfind('\n', own.size() - 2) + 1);
  const GateResult late = gate(shifted);
  EXPECT_FALSE(late.pass);
  EXPECT_EQ(late.detail.rfind("200 lines; 199 disagree", 0), 0u) << late.detail;
  // One line dropped.
  EXPECT_EQ(gate(shifted.substr(0, shifted.rfind('\n', shifted.size() - 2) + 1)).detail,
            "199 lines, the trajectory 200 frames");
  // Zeros: Sibernetic's file for a configuration not named a worm, not for this worm.
  std::string zeros;
  for (int i = 0; i < 200; ++i) zeros += kinematics::FormatMuscleLogLine({});
  const GateResult silent = gate(zeros);
  EXPECT_FALSE(silent.pass);
  EXPECT_EQ(silent.detail.rfind("200 lines; 199 disagree", 0), 0u) << silent.detail;
  // Not a log: the reader's one line, naming file and line.
  const GateResult garbled = gate(own.substr(0, 100) + "\n");
  EXPECT_FALSE(garbled.pass);
  EXPECT_NE(garbled.detail.find("muscles_activity_buffer.txt:1: "), std::string::npos)
      << garbled.detail;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace owval::ci
