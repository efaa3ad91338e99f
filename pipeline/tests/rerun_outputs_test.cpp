// A run into a directory an earlier run wrote leaves only its own outputs there: the earlier
// run's OME-Zarr store, and the partial trajectories of an interrupted run whose checkpoint was
// removed to start afresh, go with the new run's commit; a user's own files stay.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "owval/base/atomic_output.hpp"
#include "owval/pipeline/run_directory.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval::pipeline {
namespace {
namespace fs = std::filesystem;

const fs::path kDemo1 = fs::path(OWVAL_SHARED_DIR) / "reference/demo1/configuration";

RunRequest ShortDemo1Run(const fs::path& out) {
  RunRequest r;
  r.config = kDemo1.string();
  r.time_s = 0.002;  // 100 steps
  r.log_step = 20;
  r.out = out.string();
  r.no_fields = true;
  return r;
}

RunDirectorySummary RunInto(const RunRequest& r, RunDirectoryOptions options = {}) {
  const engine::SiberneticConfig config = scenarios::ResolveConfig(r.config, ".");
  RunDirectorySummary summary;
  RunIntoDirectory(config, r, options, &summary);
  return summary;
}

bool ReferenceMissing() {
  if (fs::exists(kDemo1)) return false;
  if (std::getenv("OWVAL_REQUIRE_REFERENCE")) ADD_FAILURE() << "no " << kDemo1;
  return true;
}

TEST(RerunOutputs, ARunWithoutZarrRemovesTheEarlierRunsStore) {
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kDemo1;
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
  if (ReferenceMissing()) GTEST_SKIP() << "no " << kDemo1;
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

}  // namespace
}  // namespace owval::pipeline
