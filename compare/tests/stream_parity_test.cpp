// Issue 16: CompareFrameSources on files read frame by frame gives exactly the report
// CompareTrajectories gives on the same files read whole (every gate value, series, frame and
// drift, compared through the JSON report at 17 significant digits), on real reference files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "owval/compare/parity.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::compare {
namespace {
namespace fs = std::filesystem;

const fs::path kReference = fs::path(OWVAL_SHARED_DIR) / "reference";

fs::path TempPath(const std::string& name) { return owval::testing::TestScratch() / name; }

void ExpectStreamedEqualsWhole(const fs::path& reference, const fs::path& candidate,
                               const ParityOptions& options) {
  const ParityReport whole =
      CompareTrajectories(ReadTrajectory(reference), ReadTrajectory(candidate), options);
  const auto refs = OpenFrameSource(reference), cands = OpenFrameSource(candidate);
  const ParityReport streamed = CompareFrameSources(*refs, *cands, options);
  EXPECT_EQ(streamed.ToJson().dump(), whole.ToJson().dump());
  EXPECT_EQ(streamed.ToTable(), whole.ToTable());
  EXPECT_GT(whole.gates.size(), 8u);
}

TEST(StreamedParity, Demo1AgainstItsOneSecondRunEqualsTheWholeReport) {
  // Log steps 20 and 100: every fifth reference frame paired.
  ExpectStreamedEqualsWhole(kReference / "demo1/position_buffer.txt",
                            kReference / "demo1_1s/position_buffer.txt", {});
}

TEST(StreamedParity, SampledFramesAndAGroupTrackEqualTheWholeReport) {
  ParityOptions o;
  o.track = Track{0, "elastic", Axis::kX};
  o.sample_frames = {0, 5, 95, 10, 5};  // out of order, one twice
  ExpectStreamedEqualsWhole(kReference / "demo1/position_buffer.txt",
                            kReference / "demo1_1s/position_buffer.txt", o);
}

TEST(StreamedParity, WormGatesOnGzipTextAgainstHdf5EqualTheWholeReport) {
  // The worm (worm.* gates) against an HDF5 copy whose body is 1% taller and shifted in x.
  const fs::path worm = kReference / "worm_alone_0.6s/position_buffer.txt.gz";
  Trajectory changed = ReadTrajectory(worm);
  for (std::size_t f = 0; f < changed.frame_count(); ++f)
    for (std::size_t p = 0; p < changed.particle_count(); ++p)
      if (KindOf(changed.type[p]) == ParticleKind::kElastic) {
        changed.position(f, p)[1] *= 1.01f;
        changed.position(f, p)[0] += 0.002f * float(f);
      }
  const fs::path h5 = TempPath("worm_changed.h5");
  WriteHdf5(changed, h5);
  ParityOptions o;
  o.track = Track{0, "all", Axis::kY};
  ExpectStreamedEqualsWhole(worm, h5, o);
  const auto refs = OpenFrameSource(worm), cands = OpenFrameSource(h5);
  const ParityReport r = CompareFrameSources(*refs, *cands, o);
  ASSERT_NE(r.gate("worm.span"), nullptr);
  EXPECT_GT(r.gate("worm.centre_of_mass")->value, 0);
}

}  // namespace
}  // namespace owval::compare
