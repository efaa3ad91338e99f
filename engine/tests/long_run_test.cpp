// Long runs (issue 16): streamed outputs, checkpoints, interrupts and resume with identical bytes.
#include "owval/engine/long_run.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <map>
#include <random>

#include "long_run_support.hpp"
#include "owval/base/errors.hpp"
#include "owval/engine/config.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval::engine {
namespace {
using namespace owval::testing;

RunOptions Demo1Options(double duration_s, int log_step) {
  RunOptions o;
  o.duration_s = duration_s;
  o.log_step = log_step;
  return o;
}

void ExpectSameOutputs(const fs::path& a, const fs::path& b) {
  EXPECT_EQ(Bytes(a / "position_buffer.txt"), Bytes(b / "position_buffer.txt"));
  ExpectSameHdf5Datasets(a / "trajectory.h5", b / "trajectory.h5");
}

TEST(LongRun, StreamedOutputsEqualTheInMemoryRunsWriters) {
  const SiberneticConfig config = ReadSiberneticConfig(kDemo1);
  const RunOptions o = Demo1Options(0.004, 10);  // 200 steps, 20 frames (a chunk and a bit)
  const fs::path streamed = ScratchDir("streamed"), whole = ScratchDir("whole");
  LongRunOptions files;
  files.out = streamed;
  const RunSummary s = RunToFiles(config, o, files);
  EXPECT_EQ(s.frames, 20u);
  EXPECT_FALSE(s.interrupted);
  const Trajectory t = engine::Run(config, o);
  WriteSiberneticText(t, whole / "position_buffer.txt", TextLayout::kOpenCL);
  WriteHdf5(t, whole / "trajectory.h5");
  ExpectSameOutputs(streamed, whole);
  EXPECT_FALSE(fs::exists(PartialPath(streamed / "trajectory.h5")));
}

TEST(LongRun, InterruptedThenResumedEqualsUninterruptedByteForByte) {
  const SiberneticConfig config = ReadSiberneticConfig(kDemo1);
  RunOptions o = Demo1Options(0.01, 10);  // 500 steps, 50 frames
  const fs::path whole = ScratchDir("uninterrupted"), cut = ScratchDir("interrupted");
  LongRunOptions files;
  files.out = whole;
  RunToFiles(config, o, files);
  // Stop at step 337: 34 frames, 32 of them in HDF5 chunks and 2 pending in the checkpoint.
  std::size_t steps = 0;
  o.on_step = [&](std::size_t done, std::size_t) { steps = done; };
  o.stop_requested = [&] { return steps == 337; };
  o.checkpoint_every = 100;
  files.out = cut;
  files.invocation = "the arguments";
  const RunSummary stopped = RunToFiles(config, o, files);
  EXPECT_TRUE(stopped.interrupted);
  EXPECT_EQ(stopped.steps, 337u);
  EXPECT_TRUE(fs::exists(cut / "position_buffer.partial.txt"));
  EXPECT_FALSE(fs::exists(cut / "trajectory.h5"));
  const Trajectory partial = ReadHdf5(cut / "trajectory.partial.h5");
  EXPECT_EQ(partial.provenance.at("partial"), "1");
  EXPECT_EQ(partial.frame_count(), 34u);
  EXPECT_EQ(ReadCheckpointInvocation(cut), "the arguments");
  o.stop_requested = nullptr;
  files.resume = true;
  const RunSummary resumed = RunToFiles(config, o, files);
  EXPECT_EQ(resumed.first_step, 337u);
  EXPECT_EQ(resumed.frames, 50u);
  ExpectSameOutputs(whole, cut);
  EXPECT_FALSE(fs::exists(cut / "trajectory.partial.h5"));
}

// Runs demo1 for 500 steps (50 frames) into `dir`, stopped (the SIGINT/SIGTERM path: a stop
// checkpoint, then the outputs finished as partial files) after each step of `stops` in turn and
// resumed; checkpoints every `every` steps (0: none but the stops').
void RunStoppedAndResumed(const fs::path& dir, std::size_t every,
                          const std::vector<std::size_t>& stops) {
  const SiberneticConfig config = ReadSiberneticConfig(kDemo1);
  RunOptions o = Demo1Options(0.01, 10);
  o.checkpoint_every = every;
  std::size_t steps = 0, stop = 0;
  o.on_step = [&](std::size_t done, std::size_t) { steps = done; };
  o.stop_requested = [&] { return steps == stop; };
  LongRunOptions files;
  files.out = dir;
  for (std::size_t at : stops) {
    stop = at;
    const RunSummary s = RunToFiles(config, o, files);
    ASSERT_TRUE(s.interrupted);
    ASSERT_EQ(s.steps, at);
    ASSERT_EQ(ReadHdf5(dir / "trajectory.partial.h5").frame_count(), (at + 9) / 10);
    files.resume = true;
  }
  o.stop_requested = nullptr;
  EXPECT_EQ(RunToFiles(config, o, files).first_step, stops.back());
}

// Stopping by a signal finished the HDF5 file in place (partial mark, frames since the
// checkpoint) after a checkpoint at the stop that closed and reopened it: the resumed file had
// the uninterrupted one's datasets, not its bytes. Stops at a periodic checkpoint's step, between
// two, before the first, twice, and without periodic checkpoints.
TEST(LongRun, StoppedHdf5FileResumedEqualsUninterruptedFileByteForByte) {
  // Checkpoints close and reopen the file: an uninterrupted run's layout depends on them.
  const SiberneticConfig config = ReadSiberneticConfig(kDemo1);
  std::map<std::size_t, fs::path> uninterrupted;
  for (std::size_t every : {0, 100}) {
    RunOptions o = Demo1Options(0.01, 10);
    o.checkpoint_every = every;
    LongRunOptions files;
    files.out = uninterrupted[every] = ScratchDir("bytes_whole" + std::to_string(every));
    RunToFiles(config, o, files);
  }
  const std::vector<std::pair<std::size_t, std::vector<std::size_t>>> cases = {
      {100, {300}}, {100, {337}}, {100, {60}}, {100, {137, 420}}, {0, {337}}, {0, {137, 420}}};
  int k = 0;
  for (const auto& [every, stops] : cases) {
    const fs::path cut = ScratchDir("bytes_cut" + std::to_string(k++));
    SCOPED_TRACE("checkpoints every " + std::to_string(every) + " steps, stopped after step " +
                 std::to_string(stops.front()) + (stops.size() > 1 ? " and more" : ""));
    RunStoppedAndResumed(cut, every, stops);
    const fs::path& whole = uninterrupted[every];
    for (const char* output : {"trajectory.h5", "position_buffer.txt"})
      EXPECT_TRUE(Bytes(whole / output) == Bytes(cut / output))
          << output << " differs: " << fs::file_size(whole / output) << " bytes uninterrupted, "
          << (fs::exists(cut / output) ? fs::file_size(cut / output) : 0) << " resumed";
    for (const auto& entry : fs::directory_iterator(cut))  // nothing but the two outputs
      EXPECT_TRUE(entry.path().filename() == "trajectory.h5" ||
                  entry.path().filename() == "position_buffer.txt")
          << entry.path();
  }
}

TEST(LongRun, ResumeRefusesAnotherConfiguration) {
  SiberneticConfig config = ReadSiberneticConfig(kDemo1);
  RunOptions o = Demo1Options(0.002, 10);
  const fs::path dir = ScratchDir("other");
  o.stop_requested = [] { return true; };
  LongRunOptions files;
  files.out = dir;
  EXPECT_TRUE(RunToFiles(config, o, files).interrupted);
  config.position[0][0] += 0.5f;
  files.resume = true;
  o.stop_requested = nullptr;
  EXPECT_THROW(RunToFiles(config, o, files), InputError);
}

TEST(LongRun, XpbdInterruptedThenResumedEqualsUninterruptedByteForByte) {
  const SiberneticConfig config = ReadSiberneticConfig(kDemo1);
  RunOptions o = Demo1Options(0.002, 10);  // 100 steps (55 substeps each), 10 frames
  o.backend = "xpbd";
  const fs::path whole = ScratchDir("xpbd_whole"), cut = ScratchDir("xpbd_cut");
  LongRunOptions files;
  files.out = whole;
  RunToFiles(config, o, files);
  std::size_t steps = 0;
  o.on_step = [&](std::size_t done, std::size_t) { steps = done; };
  o.stop_requested = [&] { return steps == 37; };
  o.checkpoint_every = 20;
  files.out = cut;
  EXPECT_TRUE(RunToFiles(config, o, files).interrupted);
  o.stop_requested = nullptr;
  files.resume = true;
  const RunSummary resumed = RunToFiles(config, o, files);
  EXPECT_EQ(resumed.first_step, 37u);
  ExpectSameOutputs(whole, cut);
}

TEST(LongRun, WcsphCannotCheckpointAndSaysSo) {
  RunOptions o = Demo1Options(0.002, 10);
  o.backend = "wcsph";
  o.checkpoint_every = 10;
  LongRunOptions files;
  files.out = ScratchDir("wcsph");
  SiberneticConfig liquid;  // WCSPH takes liquid and boundary particles only
  liquid.source = "two liquid particles";
  liquid.box = {0, 100, 0, 100, 0, 100};
  liquid.position = {{50, 50, 50, 1.1f}, {51.5f, 50, 50, 1.1f}};
  liquid.velocity.assign(2, {0, 0, 0, 0});
  try {
    RunToFiles(liquid, o, files);
    FAIL() << "wcsph checkpointed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("backend wcsph cannot checkpoint"), std::string::npos)
        << e.what();
  }
}

TEST(LongRun, AnInterruptedWcsphRunKeepsItsPartialTrajectoryWithoutACheckpoint) {
  RunOptions o = Demo1Options(0.002, 10);
  o.backend = "wcsph";
  std::size_t steps = 0;
  o.on_step = [&](std::size_t done, std::size_t) { steps = done; };
  o.stop_requested = [&] { return steps == 25; };
  LongRunOptions files;
  files.out = ScratchDir("wcsph_interrupted");
  SiberneticConfig liquid;
  liquid.source = "two liquid particles";
  liquid.box = {0, 100, 0, 100, 0, 100};
  liquid.position = {{50, 50, 50, 1.1f}, {51.5f, 50, 50, 1.1f}};
  liquid.velocity.assign(2, {0, 0, 0, 0});
  const RunSummary s = RunToFiles(liquid, o, files);
  EXPECT_TRUE(s.interrupted);
  EXPECT_FALSE(s.checkpointed);
  EXPECT_EQ(s.steps, 25u);
  EXPECT_EQ(ReadHdf5(files.out / "trajectory.partial.h5").frame_count(), 3u);
  EXPECT_TRUE(fs::exists(files.out / "position_buffer.partial.txt"));
  EXPECT_FALSE(fs::exists(CheckpointPath(files.out)));
}

// The inode of the current checkpoint file (each checkpoint is a new file renamed into place), 0
// when there is none.
ino_t CheckpointInode(const fs::path& out) {
  struct stat st {};
  return ::stat(CheckpointPath(out).c_str(), &st) == 0 ? st.st_ino : 0;
}

// A resumption refused because the HDF5 temporary is truncated changes no file: the text
// temporary, longer than its checkpoint after a kill (here by a row written past it), was cut
// back to it before the HDF5 one was found unreadable. The HDF5 file is put back afterwards.
void ExpectARefusedResumptionToChangeNothing(const fs::path& out) {
  for (const auto& entry : fs::directory_iterator(out))
    if (entry.path().filename().string().rfind(".position_buffer.txt.tmp.", 0) == 0)
      std::ofstream(entry.path(), std::ios::app) << "1\t2\t3\t2.1\n";
  std::map<fs::path, std::string> before;
  fs::path hdf5;
  for (const auto& entry : fs::directory_iterator(out)) {
    if (!entry.is_regular_file()) continue;
    before[entry.path()] = Bytes(entry.path());
    if (entry.path().filename().string().rfind(".trajectory.h5.tmp.", 0) == 0) hdf5 = entry.path();
  }
  ASSERT_FALSE(hdf5.empty()) << "no HDF5 temporary in " << out;
  fs::resize_file(hdf5, 1000);  // shorter than any checkpoint's: it holds the superblock and frames
  const Finished refused = RunOwval({"run", "--resume", out.string()}, out.string() + ".r.log");
  EXPECT_EQ(refused.exit_code, 2) << Bytes(out.string() + ".r.log");
  std::ofstream(hdf5, std::ios::binary) << before[hdf5];
  for (const auto& [path, bytes] : before) EXPECT_TRUE(Bytes(path) == bytes) << path;
}

// The process is killed (SIGKILL: no handler, no flush) at a random step past a checkpoint: after
// a random number of checkpoints (1-4 of 9) and a random delay; --resume then finishes it.
TEST(LongRunProcess, KilledPastACheckpointThenResumedEqualsUninterrupted) {
  const fs::path whole = ScratchDir("cli_whole"), killed = ScratchDir("cli_killed");
  const std::vector<std::string> run = {"run",  kDemo1.string(), "--time",
                                        "0.05", "--log-step",    "20"};
  auto args = [&](const fs::path& out, std::vector<std::string> extra) {
    std::vector<std::string> all = run;
    all.insert(all.end(), {"--out", out.string()});
    all.insert(all.end(), extra.begin(), extra.end());
    return all;
  };
  ASSERT_EQ(RunOwval(args(whole, {}), whole.string() + ".log").exit_code, 0);
  std::random_device seed;
  std::mt19937 random(seed());
  const int checkpoints = std::uniform_int_distribution<int>(1, 4)(random);
  const int delay_ms = std::uniform_int_distribution<int>(0, 100)(random);
  SCOPED_TRACE("killed " + std::to_string(delay_ms) + " ms after checkpoint " +
               std::to_string(checkpoints));
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = Start(args(killed, {"--checkpoint-every", "250"}), killed.string() + ".log");
  ino_t seen = 0;
  for (int k = 0; k < checkpoints; ++k) {
    ASSERT_TRUE(
        WaitFor([&] { return CheckpointInode(killed) != seen && CheckpointInode(killed); }, 120));
    seen = CheckpointInode(killed);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
  ::kill(pid, SIGKILL);
  const Finished f = Wait(pid, start);
  ASSERT_EQ(f.signal, SIGKILL) << "the run ended before the kill";
  EXPECT_FALSE(fs::exists(killed / "trajectory.h5"));
  ExpectARefusedResumptionToChangeNothing(killed);
  const Finished resumed =
      RunOwval({"run", "--resume", killed.string()}, killed.string() + ".2.log");
  ASSERT_EQ(resumed.exit_code, 0) << Bytes(killed.string() + ".2.log");
  ExpectSameOutputs(whole, killed);
  for (const auto& entry : fs::directory_iterator(killed))  // no temporary left behind
    EXPECT_NE(entry.path().filename().string().rfind(".", 0), 0u) << entry.path();
}

// SIGTERM (exit 143: a stop checkpoint, the outputs finished as partial files) past a checkpoint,
// then --resume: the files equal an uninterrupted run's byte for byte, as after a SIGKILL (the
// HDF5 file was 1-2 kB longer: same datasets, other layout), and nothing else is left.
TEST(LongRunProcess, SigtermPastACheckpointThenResumedEqualsUninterruptedByteForByte) {
  const fs::path whole = ScratchDir("cli_term_whole"), stopped = ScratchDir("cli_term");
  auto args = [&](const fs::path& out) {
    return std::vector<std::string>{
        "run",        kDemo1.string(),      "--time", "0.05", "--log-step", "20", "--out",
        out.string(), "--checkpoint-every", "250"};
  };
  ASSERT_EQ(RunOwval(args(whole), whole.string() + ".log").exit_code, 0);
  std::random_device seed;
  const int delay_ms = std::uniform_int_distribution<int>(0, 300)(seed);
  SCOPED_TRACE("stopped " + std::to_string(delay_ms) + " ms after the first checkpoint");
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = Start(args(stopped), stopped.string() + ".log");
  ASSERT_TRUE(WaitFor([&] { return CheckpointInode(stopped) != 0; }, 120));
  std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
  ::kill(pid, SIGTERM);
  const Finished f = Wait(pid, start);
  ASSERT_EQ(f.exit_code, 143) << "the run ended before the signal";
  ASSERT_TRUE(fs::exists(stopped / "trajectory.partial.h5"));
  const Finished resumed =
      RunOwval({"run", "--resume", stopped.string()}, stopped.string() + ".2.log");
  ASSERT_EQ(resumed.exit_code, 0) << Bytes(stopped.string() + ".2.log");
  for (const char* output : {"trajectory.h5", "position_buffer.txt"})
    EXPECT_TRUE(Bytes(whole / output) == Bytes(stopped / output))
        << output << " differs: " << fs::file_size(whole / output) << " bytes uninterrupted, "
        << (fs::exists(stopped / output) ? fs::file_size(stopped / output) : 0) << " resumed";
  for (const auto& entry : fs::directory_iterator(stopped))  // no temporary or partial file left
    EXPECT_TRUE(entry.path().filename() == "trajectory.h5" ||
                entry.path().filename() == "position_buffer.txt")
        << entry.path();
}

// SIGINT: exit 130, a readable partial trajectory under names that say so, a checkpoint, and
// owval inspect saying "partial".
TEST(LongRunProcess, SigintLeavesAReadablePartialTrajectoryAndACheckpoint) {
  const fs::path dir = ScratchDir("cli_sigint");
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid =
      Start({"run", kDemo1.string(), "--time", "0.2", "--log-step", "20", "--out", dir.string()},
            dir.string() + ".log");
  // Some frames in: the text writer's temporary exists once the HDF5 one does.
  ASSERT_TRUE(WaitFor(
      [&] {
        if (!fs::exists(dir)) return false;
        for (const auto& e : fs::directory_iterator(dir))
          if (e.path().filename().string().find("trajectory.h5.tmp") != std::string::npos)
            return true;
        return false;
      },
      120));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ::kill(pid, SIGINT);
  const Finished f = Wait(pid, start);
  EXPECT_EQ(f.exit_code, 130) << Bytes(dir.string() + ".log");
  EXPECT_NE(Bytes(dir.string() + ".log").find("--resume"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "trajectory.h5"));
  EXPECT_FALSE(fs::exists(dir / "position_buffer.txt"));
  EXPECT_TRUE(fs::exists(CheckpointPath(dir)));
  const Trajectory h5 = ReadHdf5(dir / "trajectory.partial.h5");
  EXPECT_EQ(h5.provenance.at("partial"), "1");
  EXPECT_GT(h5.frame_count(), 0u);
  const Trajectory text = ReadTrajectory(dir / "position_buffer.partial.txt");
  EXPECT_EQ(text.frame_count(), h5.frame_count());
  EXPECT_TRUE(SameBits(text.type, h5.type));
  const Finished inspect =
      RunOwval({"inspect", (dir / "trajectory.partial.h5").string()}, dir.string() + ".i.log");
  EXPECT_EQ(inspect.exit_code, 0);
  EXPECT_NE(Bytes(dir.string() + ".i.log").find("partial"), std::string::npos)
      << Bytes(dir.string() + ".i.log");
}

// A run started with a relative configuration path in a folder whose name has a space,
// interrupted, then resumed from another working directory: the checkpoint holds the
// configuration's absolute path, and the printed hint is one shell word.
TEST(LongRunProcess, ResumesFromAnotherDirectoryAndQuotesItsHint) {
  const fs::path dir = ScratchDir("resume here"), parent = dir.parent_path();
  fs::copy_file(kDemo1, parent / "my demo1.cfg", fs::copy_options::overwrite_existing);
  const fs::path was = fs::current_path();
  fs::current_path(parent);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = Start({"run", "my demo1.cfg", "--time", "0.2", "--log-step", "20",
                           "--checkpoint-every", "250", "--out", "resume here"},
                          parent / "resume_here.log");
  const bool checkpointed = WaitFor([&] { return CheckpointInode(dir) != 0; }, 120);
  ::kill(pid, SIGINT);
  const Finished f = Wait(pid, start);
  fs::current_path("/");
  const std::string log = Bytes(parent / "resume_here.log");
  ASSERT_TRUE(checkpointed) << log;
  ASSERT_EQ(f.exit_code, 130) << log;
  EXPECT_NE(log.find("continue with: owval run --resume 'resume here'"), std::string::npos) << log;
  const Finished resumed = RunOwval({"run", "--resume", dir.string()}, parent / "resumed.log");
  fs::current_path(was);
  ASSERT_EQ(resumed.exit_code, 0) << Bytes(parent / "resumed.log");
  EXPECT_TRUE(fs::exists(dir / "trajectory.h5"));
}

}  // namespace
}  // namespace owval::engine
