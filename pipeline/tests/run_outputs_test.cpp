// What `owval run` leaves in its output directory besides the trajectories.
// - A muscle-driven run writes Sibernetic's muscles_activity_buffer.txt with its other outputs: a
//   short run of Sibernetic's worm configuration writes the lines of the reference's own file
//   byte for byte, a run stopped and resumed writes the same bytes as one run straight through,
//   and a run without muscles writes none (nor leaves an earlier run's).
// - A run into a directory an earlier run wrote leaves only its own outputs there: the earlier
//   run's OME-Zarr store, and the partial trajectories of an interrupted run whose checkpoint was
//   removed to start afresh, go with the new run's commit; a user's own files stay. So does an
//   earlier failed run's state dump.
#include <gtest/gtest.h>
#include <libdeflate.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/run.hpp"
#include "owval/pipeline/run_directory.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval::pipeline {
namespace {
namespace fs = std::filesystem;

const fs::path kRun = fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s";
const fs::path kDemo1 = fs::path(OWVAL_SHARED_DIR) / "reference/demo1/configuration";
const fs::path kOneSprig = fs::path(OWVAL_SHARED_DIR) / "reference/one_sprig/configuration";
constexpr const char* kLog = "muscles_activity_buffer.txt";

// A positions-only run of `config` for `time_s` into `out`.
RunRequest ShortRun(const fs::path& config, double time_s, int log_step, const fs::path& out) {
  RunRequest r;
  r.config = config.string();
  r.time_s = time_s;
  r.log_step = log_step;
  r.out = out.string();
  r.no_fields = true;
  return r;
}

// 451 steps of 2e-5 s (Sibernetic's count: int(0.00903 / 2e-5)), logged every 150 as the
// reference was: frames after iterations 0, 150, 300 and 450.
RunRequest ShortWormRun(const fs::path& out) {
  return ShortRun(kRun / "configuration", 0.00903, 150, out);
}
RunRequest ShortDemo1Run(const fs::path& out) { return ShortRun(kDemo1, 0.002, 20, out); }

RunDirectorySummary RunInto(const RunRequest& r, RunDirectoryOptions options = {}) {
  const engine::SiberneticConfig config = scenarios::ResolveConfig(r.config, ".");
  RunDirectorySummary summary;
  RunIntoDirectory(config, r, options, &summary);
  return summary;
}

// one_sprig run into `out` and stopped after 100 of its steps; whether it left a checkpoint.
bool StopAfterOneHundredSteps(const fs::path& out) {
  std::atomic<int> polls{0};
  RunDirectoryOptions stopping;
  stopping.stop_requested = [&polls] { return ++polls > 100; };
  return RunInto(ShortRun(kOneSprig, 0.01, 10, out), stopping).run.checkpointed;
}

// The first `lines` lines of `text`.
std::string Head(const std::string& text, std::size_t lines) {
  std::size_t at = 0;
  for (std::size_t i = 0; i < lines && at != std::string::npos; ++i) {
    at = text.find('\n', at);
    if (at != std::string::npos) ++at;
  }
  return text.substr(0, at);
}

bool ReferenceMissing() {
  if (fs::exists(kRun / kLog) && fs::exists(kRun / "configuration") && fs::exists(kOneSprig))
    return false;
  if (std::getenv("OWVAL_REQUIRE_REFERENCE")) ADD_FAILURE() << "no " << kRun;
  return true;
}

TEST(MuscleLogOutput, AShortWormRunWritesTheReferencesFirstLines) {
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kRun;
  const fs::path out = owval::testing::TestScratch("muscles_short");
  const RunDirectorySummary s = RunInto(ShortWormRun(out));
  ASSERT_TRUE(s.run.muscles_driven);
  ASSERT_EQ(s.run.frames, 4u);
  EXPECT_NE(std::find(s.outputs.begin(), s.outputs.end(), (out / kLog).string()), s.outputs.end());
  const std::string written = ReadWholeFile(out / kLog);
  EXPECT_EQ(written, Head(ReadWholeFile(kRun / kLog), 4));
  EXPECT_NE(written.find("6.108888e-03"), std::string::npos);  // line 2 is not all zeros
}

TEST(MuscleLogOutput, AResumedRunWritesTheSameBytes) {
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kRun;
  const fs::path straight = owval::testing::TestScratch("muscles_straight");
  RunInto(ShortWormRun(straight));
  const fs::path resumed = owval::testing::TestScratch("muscles_resumed");
  std::atomic<int> polls{0};
  RunDirectoryOptions stopping;
  stopping.stop_requested = [&polls] { return ++polls > 200; };  // after 200 steps
  const RunDirectorySummary first = RunInto(ShortWormRun(resumed), stopping);
  ASSERT_TRUE(first.run.interrupted);
  ASSERT_TRUE(first.run.checkpointed);
  EXPECT_FALSE(fs::exists(resumed / kLog));  // an interrupted run writes no side file
  RunDirectoryOptions resume;
  resume.resume = true;
  const RunDirectorySummary second = RunInto(ShortWormRun(resumed), resume);
  ASSERT_FALSE(second.run.interrupted);
  EXPECT_EQ(second.run.first_step, 200u);
  EXPECT_EQ(ReadWholeFile(resumed / kLog), ReadWholeFile(straight / kLog));
}

TEST(MuscleLogOutput, ARunWithoutMusclesWritesNone) {
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kRun;
  const fs::path out = owval::testing::TestScratch("muscles_off");
  RunRequest r = ShortWormRun(out);
  r.muscles = "off";
  r.time_s = 0.0002;  // 10 steps
  r.log_step = 5;
  const RunDirectorySummary s = RunInto(r);
  EXPECT_FALSE(s.run.muscles_driven);
  EXPECT_TRUE(fs::exists(out / "worm_motion_log.txt"));
  EXPECT_FALSE(fs::exists(out / kLog));
}

// A rerun into the same directory with the muscles off: the first run's log would otherwise be
// read as the second's (checklist item 3 and `ci validate` check it against the trajectory).
TEST(MuscleLogOutput, ARerunWithoutMusclesRemovesTheEarlierLog) {
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kRun;
  const fs::path out = owval::testing::TestScratch("muscles_rerun_off");
  RunRequest r = ShortWormRun(out);
  r.time_s = 0.0002;  // 10 steps
  r.log_step = 5;
  ASSERT_TRUE(RunInto(r).run.muscles_driven);
  ASSERT_TRUE(fs::exists(out / kLog));
  std::ofstream(out / "notes.txt") << "the user's own file";
  r.muscles = "off";
  const RunDirectorySummary s = RunInto(r);
  EXPECT_FALSE(s.run.muscles_driven);
  EXPECT_FALSE(fs::exists(out / kLog));
  EXPECT_TRUE(fs::exists(out / "worm_motion_log.txt"));
  EXPECT_TRUE(fs::exists(out / "notes.txt"));  // only the names owval writes
  EXPECT_FALSE(fs::exists(CommitMarkerPath(out)));
}

bool Demo1Missing() {
  if (fs::exists(kDemo1)) return false;
  if (std::getenv("OWVAL_REQUIRE_REFERENCE")) ADD_FAILURE() << "no " << kDemo1;
  return true;
}

TEST(RerunOutputs, ARunWithoutZarrRemovesTheEarlierRunsStore) {
  if (Demo1Missing()) GTEST_SKIP() << "no " << kDemo1;
  const fs::path out = owval::testing::TestScratch("rerun_zarr");
  RunRequest r = ShortDemo1Run(out);
  r.zarr = true;
  RunInto(r);
  ASSERT_TRUE(fs::is_directory(out / "trajectory.zarr"));
  fs::create_directory(out / "my_notes");
  r.zarr = false;
  RunInto(r);
  EXPECT_FALSE(fs::exists(out / "trajectory.zarr"));
  EXPECT_TRUE(fs::is_directory(out / "my_notes"));
  EXPECT_TRUE(fs::exists(out / "position_buffer.txt"));
}

TEST(RerunOutputs, AFreshRunRemovesAnAbandonedRunsPartialTrajectories) {
  if (Demo1Missing()) GTEST_SKIP() << "no " << kDemo1;
  const fs::path out = owval::testing::TestScratch("rerun_partial");
  RunDirectoryOptions stopping;
  int polls = 0;
  stopping.stop_requested = [&polls] { return ++polls > 50; };
  ASSERT_TRUE(RunInto(ShortDemo1Run(out), stopping).run.interrupted);
  ASSERT_TRUE(fs::exists(PartialPath(out / "trajectory.h5")));
  fs::remove_all(out / "checkpoint");  // the user starts afresh
  ASSERT_FALSE(RunInto(ShortDemo1Run(out)).run.interrupted);
  EXPECT_FALSE(fs::exists(PartialPath(out / "trajectory.h5")));
  EXPECT_FALSE(fs::exists(PartialPath(out / "position_buffer.txt")));
  EXPECT_TRUE(fs::exists(out / "trajectory.h5"));
}

// Two liquid particles at one point: the pressure's direction is 0/0 at the first integration.
engine::SiberneticConfig TwoLiquidParticlesAtOnePoint() {
  engine::SiberneticConfig c;
  c.source = "two_particles";
  c.box = {0, 100, 0, 100, 0, 100};
  c.position = {{50, 50, 50, 1.1f}, {50, 50, 50, 1.1f}};
  c.velocity.assign(2, {0, 0, 0, 0});
  return c;
}

TEST(RerunOutputs, ACompletedRunRemovesAnEarlierFailedRunsStateDump) {
  const fs::path out = owval::testing::TestScratch("rerun_dump");
  RunRequest r = ShortRun("two_particles", 10 * 2e-5, 1, out);
  RunDirectorySummary failed;
  EXPECT_THROW(RunIntoDirectory(TwoLiquidParticlesAtOnePoint(), r, {}, &failed), SimulationError);
  ASSERT_TRUE(fs::exists(engine::StateDumpPath(out, 1)));
  std::ofstream(out / "owval_nan_dump_step1.txt.notes") << "mine\n";
  std::ofstream(out / "owval_nan_dump_stepX.txt") << "mine\n";
  engine::SiberneticConfig apart = TwoLiquidParticlesAtOnePoint();
  apart.position[1][0] = 60;
  RunDirectorySummary completed;
  RunIntoDirectory(apart, r, {}, &completed);
  EXPECT_FALSE(fs::exists(engine::StateDumpPath(out, 1)));
  EXPECT_TRUE(fs::exists(out / "owval_nan_dump_step1.txt.notes"));
  EXPECT_TRUE(fs::exists(out / "owval_nan_dump_stepX.txt"));
  EXPECT_TRUE(fs::exists(out / "trajectory.h5"));
}

TEST(RerunOutputs, AStateDumpsNameIsRecognisedOnlyInItsOwnForm) {
  EXPECT_TRUE(engine::IsStateDumpName(engine::StateDumpPath("d", 0)));
  EXPECT_TRUE(engine::IsStateDumpName(engine::StateDumpPath("d", 123456)));
  for (const char* other :
       {"owval_nan_dump_step.txt", "owval_nan_dump_step1.txt.gz", "owval_nan_dump_step-1.txt",
        "xowval_nan_dump_step1.txt", "owval_nan_dump_step1a.txt", "position_buffer.txt"})
    EXPECT_FALSE(engine::IsStateDumpName(other)) << other;
}

// A checkpoint's recorded arguments changed in place to another type: the line was nlohmann's
// "[json.exception.type_error.302] type must be string, but is number" (and a byte flipped in
// their JSON, "[json.exception.parse_error.101] ..."). Now the field and what was expected.
TEST(RunCheckpoint, RecordedArgumentsOfAnotherTypeNameTheField) {
  const fs::path out = owval::testing::TestScratch("checkpoint_arguments");
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kOneSprig;
  ASSERT_TRUE(StopAfterOneHundredSteps(out));
  const std::string config = kOneSprig.string();
  EXPECT_EQ(RunRequest::FromCheckpoint(out.string()).config, config);  // as recorded
  const fs::path file = out / "checkpoint/checkpoint.bin";
  std::string bytes = ReadWholeFile(file);
  const std::string from = "\"config\":\"" + config + "\"";
  const std::string to = "\"config\":" + std::string(config.size() + 2, '1');  // same length
  const std::size_t at = bytes.find(from);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, from.size(), to);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  try {  // the checksum sees the edit first
    RunRequest::FromCheckpoint(out.string());
    ADD_FAILURE() << "an edited checkpoint was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("CRC-32 does not match"), std::string::npos) << e.what();
  }
  // Sealed again (as a writer that recorded the wrong type would have): the field is named.
  const std::uint32_t crc = libdeflate_crc32(0, bytes.data(), bytes.size() - 4);
  std::memcpy(bytes.data() + bytes.size() - 4, &crc, 4);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  try {
    RunRequest::FromCheckpoint(out.string());
    ADD_FAILURE() << "a number for config was accepted";
  } catch (const InputError& e) {
    const std::string line = e.what();
    EXPECT_NE(line.find("bad run arguments: \"config\": expected a string"), std::string::npos)
        << line;
    EXPECT_EQ(line.find("json.exception"), std::string::npos) << line;
  }
}

// A checkpoint with one byte of the solver's state flipped resumed the run from the altered state
// (exit 0); the file's CRC-32 now refuses it before anything is touched.
TEST(RunCheckpoint, AByteFlippedInTheSolversStateIsRefused) {
  const fs::path out = owval::testing::TestScratch("checkpoint_flipped");
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kOneSprig;
  ASSERT_TRUE(StopAfterOneHundredSteps(out));
  const fs::path file = out / "checkpoint/checkpoint.bin";
  std::string bytes = ReadWholeFile(file);
  bytes[bytes.size() - 1000] ^= 0x10;  // inside the solver's state, the last blob
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  const auto listing = [&out] {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(out))
      names.push_back(e.path().string() + " " +
                      (e.is_regular_file() ? std::to_string(e.file_size()) : "dir"));
    std::sort(names.begin(), names.end());
    return names;
  };
  const std::vector<std::string> before = listing();
  RunDirectoryOptions resume;
  resume.resume = true;
  try {
    RunInto(RunRequest::FromCheckpoint(out.string()), resume);
    ADD_FAILURE() << "a checkpoint with a flipped byte was resumed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("CRC-32 does not match"), std::string::npos) << e.what();
  }
  EXPECT_EQ(listing(), before);
}

}  // namespace
}  // namespace owval::pipeline
