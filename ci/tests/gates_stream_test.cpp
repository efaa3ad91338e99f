// Issue 16: ci quick-test and validate read the two trajectories frame by frame; their gates
// carry exactly the values the whole-trajectory checks give (stability, incompressibility and
// parity reports compared through their JSON), on demo1's reference text against an HDF5
// candidate with velocities, density and pressure.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "owval/base/errors.hpp"
#include "owval/ci/gates.hpp"
#include "owval/compare/parity.hpp"
#include "owval/compare/stability.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval::ci {
namespace {
namespace fs = std::filesystem;

const fs::path kDemo1 = fs::path(OWVAL_SHARED_DIR) / "reference/demo1/position_buffer.txt";

fs::path Directory(const std::string& name) { return owval::testing::TestScratch(name); }

// demo1's first 40 frames with fields: speeds from the positions, density around rest with a few
// liquid particles outside 700-1300 kg/m^3 in some frames, pressure.
Trajectory Candidate() {
  Trajectory t = ReadTrajectory(kDemo1);
  const std::size_t frames = 40, n = t.particle_count();
  t.time_s.resize(frames);
  t.positions.resize(frames * n * 3);
  for (std::size_t f = 0; f < frames; ++f)
    for (std::size_t p = 0; p < n; ++p) {
      const std::size_t g = f > 0 ? f - 1 : 0;
      for (int a = 0; a < 3; ++a)
        t.velocities.push_back((t.coordinate(f, p, a) - t.coordinate(g, p, a)) * 0.3f);
      t.density.push_back(1000.0f + 40.0f * std::sin(float(p) * 0.37f + float(f)) +
                          (p % 7 == 0 && f % 3 == 0 ? 400.0f : 0.0f));
      t.pressure.push_back(float(p % 11) * 3.5f - float(f));
    }
  return t;
}

const GateResult& Gate(const GateReport& r, const std::string& name) {
  for (const GateResult& g : r.gates)
    if (g.name == name) return g;
  throw std::runtime_error("no gate " + name);
}

TEST(StreamedGates, ValidateGivesTheWholeTrajectoryChecksValues) {
  const fs::path dir = Directory("validate");
  fs::create_symlink(kDemo1, dir / "reference.txt");
  const Trajectory cand = Candidate();
  WriteHdf5(cand, dir / "candidate.h5");
  const Trajectory ref = ReadTrajectory(kDemo1);
  const GateReport r = Validate(dir);
  EXPECT_EQ(Gate(r, "reference stability").detail, compare::CheckStability(ref).ToJson().dump());
  EXPECT_EQ(Gate(r, "candidate stability").detail, compare::CheckStability(cand).ToJson().dump());
  const compare::IncompressibilityReport density = compare::CheckIncompressibility(cand);
  EXPECT_GT(density.max_deviation, 0.3);  // the particles pushed to 1400 kg/m^3 and more
  EXPECT_EQ(Gate(r, "candidate incompressibility").detail, density.ToJson().dump());
  const compare::ParityReport parity = compare::CompareTrajectories(ref, cand, {});
  EXPECT_EQ(Gate(r, "parity").pass, parity.pass());
  EXPECT_NE(Gate(r, "parity").detail.find(std::to_string(parity.frames.size()) + " frames"),
            std::string::npos);
  // The long-run gate (density 700-1300 kg/m^3) fails the same way streamed and whole.
  const compare::StabilityReport strict =
      compare::CheckStability(cand, compare::LongRunStabilityOptions());
  EXPECT_GT(strict.density_out_of_range.count, 0u);
  const auto frames = OpenFrameSource(dir / "candidate.h5");
  EXPECT_EQ(compare::CheckStability(*frames, compare::LongRunStabilityOptions()).ToJson().dump(),
            strict.ToJson().dump());
  fs::remove_all(dir);
}

TEST(StreamedGates, QuickTestFailsACandidateWithANaNPosition) {
  const fs::path dir = Directory("quick");
  fs::create_symlink(kDemo1, dir / "reference.txt");
  Trajectory cand = Candidate();
  WriteHdf5(cand, dir / "candidate.h5");
  const GateReport ok = QuickTest(dir);
  EXPECT_TRUE(ok.pass()) << ok.ToText();
  EXPECT_EQ(Gate(ok, "candidate completed without NaN").detail,
            "40 frames, 0 non-finite particle-frames");
  EXPECT_EQ(Gate(ok, "reference completed without NaN").detail,
            std::to_string(ReadTrajectory(kDemo1).frame_count()) +
                " frames, 0 non-finite particle-frames");
  cand.position(33, 5)[1] = NAN;
  fs::remove(dir / "candidate.h5");
  WriteHdf5(cand, dir / "candidate.h5");
  const GateReport bad = QuickTest(dir);
  EXPECT_FALSE(bad.pass());
  EXPECT_FALSE(Gate(bad, "candidate completed without NaN").pass);
  EXPECT_NE(Gate(bad, "candidate completed without NaN").detail.find("not finite"),
            std::string::npos)
      << Gate(bad, "candidate completed without NaN").detail;
  fs::remove_all(dir);
}

// A failing candidate copied over the reference agrees with itself: validate passed it (exit 0)
// until the directory's reference had to be the caller's.
TEST(StreamedGates, ValidateHoldsTheDirectorysReferenceToTheCallers) {
  const fs::path bundled = owval::testing::kBundledOneSprig;
  Trajectory faster = ReadTrajectory(bundled);  // a 5% stiffer spring: resampled at 1.05x
  const Trajectory reference = faster;
  for (std::size_t f = 0; f < faster.frame_count(); ++f)
    faster.position(f, 0)[1] =
        reference.position(std::min(f * 105 / 100, reference.frame_count() - 1), 0)[1];
  const fs::path dir = Directory("copied_over");
  WriteHdf5(faster, dir / "candidate.h5");
  WriteHdf5(faster, dir / "reference.h5");
  const GateReport alone = Validate(dir);
  EXPECT_TRUE(Gate(alone, "parity").pass);  // the candidate against itself
  EXPECT_FALSE(Gate(alone, "reference is the caller's").pass);
  EXPECT_NE(Gate(alone, "reference is the caller's").detail.find("pass --reference"),
            std::string::npos);
  EXPECT_FALSE(alone.pass());
  const GateReport held = Validate(dir, {}, bundled);
  EXPECT_FALSE(Gate(held, "reference is the caller's").pass);
  EXPECT_FALSE(held.pass());
  WriteHdf5(reference, dir / "reference.h5");
  const GateReport honest = Validate(dir, {}, bundled);
  EXPECT_TRUE(Gate(honest, "reference is the caller's").pass) << honest.ToText();
  EXPECT_FALSE(Gate(honest, "parity").pass);
  // An unreadable --reference is bad input, not a failed gate.
  EXPECT_THROW(Validate(dir, {}, dir / "missing.txt"), InputError);
  fs::remove_all(dir);
}

// A run stopped on a NaN or interrupted leaves its finite frames as trajectory.partial.h5, marked
// partial. Copied in as the candidate (or the reference), quick-test said "completed without
// NaN" and validate passed every gate, though checklist item 3 refused it.
TEST(StreamedGates, APartialRunFailsQuickTestAndValidate) {
  const fs::path dir = Directory("partial");
  const Trajectory whole = ReadTrajectory(owval::testing::kBundledOneSprig);
  const auto write = [&whole](const fs::path& destination, std::size_t frames, bool stopped) {
    TrajectoryHeader header{whole.box, whole.time_step_s, whole.log_step, whole.type, {}};
    auto writer = OpenTrajectoryWriter(destination, header);
    for (std::size_t f = 0; f < frames; ++f)
      writer->AppendFrame(whole.time_s[f], whole.position(f, 0));
    stopped ? writer->Abort() : writer->Close();
  };
  write(dir / "reference.h5", whole.frame_count(), false);
  write(dir / "run.h5", 40, true);  // as run.partial.h5
  fs::rename(dir / "run.partial.h5", dir / "candidate.h5");
  const GateReport quick = QuickTest(dir);
  EXPECT_FALSE(Gate(quick, "candidate completed without NaN").pass) << quick.ToText();
  EXPECT_NE(Gate(quick, "candidate completed without NaN").detail.find("partial"),
            std::string::npos);
  EXPECT_TRUE(Gate(quick, "reference completed without NaN").pass);
  EXPECT_FALSE(quick.pass());
  const GateReport validate = Validate(dir, {}, owval::testing::kBundledOneSprig);
  EXPECT_FALSE(Gate(validate, "candidate completed").pass) << validate.ToText();
  EXPECT_TRUE(Gate(validate, "reference completed").pass);
  EXPECT_FALSE(validate.pass());
  // The same run finished: both pass those gates.
  fs::remove(dir / "candidate.h5");
  write(dir / "candidate.h5", 40, false);
  EXPECT_TRUE(Gate(QuickTest(dir), "candidate completed without NaN").pass);
  EXPECT_TRUE(Gate(Validate(dir), "candidate completed").pass);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace owval::ci
