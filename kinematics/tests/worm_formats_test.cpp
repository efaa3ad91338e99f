// WCON and OME-Zarr of Sibernetic's worm run: checked by independent readers (the WCON rules in
// wcon_schema.json + check_wcon.py with python3-jsonschema; zarr-python for the store) and
// round-tripped through owval's own reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

#include "owval/base/errors.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/kinematics/side_files.hpp"
#include "owval/kinematics/skeleton.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::kinematics {
namespace {
namespace fs = std::filesystem;

const fs::path kPython = "/usr/bin/python3";  // Debian's, where python3-zarr/jsonschema live
const fs::path kTests = fs::path(OWVAL_SOURCE_DIR) / "kinematics/tests";

const Trajectory* Worm() {
  static const Trajectory* worm = [] {
    const fs::path p =
        fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz";
    if (!fs::exists(p)) return static_cast<Trajectory*>(nullptr);
    TextReadOptions quiet;
    quiet.quiet = true;
    return new Trajectory(ReadTrajectory(p, quiet));
  }();
  return worm;
}

fs::path Temp(const std::string& name) { return owval::testing::TestScratch() / name; }

int Python(const std::string& args) {
  const std::string command = kPython.string() + " " + args + " > /dev/null";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int CheckWcon(const fs::path& file) {
  return Python((kTests / "check_wcon.py").string() + " " + (kTests / "wcon_schema.json").string() +
                " " + file.string());
}

WormTrack WormTrackOfReference() {
  WormTrack t = TrackFromTrajectory(*Worm(), {{"configuration_fnv1a64", "0"}, {"backend", "x"}});
  t.software_version = "0.1.0";
  return t;
}

TEST(Skeletons, ReadFrameByFrameTheyEqualTheWholeTrajectorys) {
  ASSERT_NE(Worm(), nullptr) << "needs ../shared/reference/worm_alone_0.6s";
  TextReadOptions quiet;
  quiet.quiet = true;
  const auto frames = OpenFrameSource(
      fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s/position_buffer.txt.gz", quiet);
  const SkeletonSeries streamed = SkeletonsFromFrames(*frames);
  const SkeletonSeries whole = SkeletonsFromTrajectory(*Worm());
  EXPECT_EQ(streamed.time_s, whole.time_s);
  EXPECT_EQ(streamed.skeletons, whole.skeletons);
  EXPECT_GT(streamed.skeletons.size(), 100u);
}

TEST(Wcon, WormWconPassesTheTrackerCommonsRules) {
  if (!Worm() || !fs::exists(kPython)) GTEST_SKIP() << "needs the worm reference and python3";
  const fs::path file = Temp("worm.wcon");
  const WormTrack track = WormTrackOfReference();
  EXPECT_EQ(track.time_s.size(), 200u);
  EXPECT_EQ(track.x_mm.front().size(), 99u);  // every midline bin of this worm has particles
  WriteWcon(track, file);
  EXPECT_EQ(CheckWcon(file), 0);
  fs::remove(file);
}

TEST(Wcon, TheRulesRejectWhatAStrictReaderWould) {
  if (!Worm() || !fs::exists(kPython)) GTEST_SKIP() << "needs the worm reference and python3";
  const fs::path file = Temp("bad.wcon");
  auto expect_rejected = [&](WormTrack bad, const char* what) {
    std::ofstream(file) << WconText(bad);  // WconText does not check: the rules must
    EXPECT_EQ(CheckWcon(file), 1) << what;
  };
  WormTrack t = WormTrackOfReference();
  WormTrack decreasing = t;
  std::swap(decreasing.time_s[3], decreasing.time_s[4]);
  expect_rejected(decreasing, "decreasing t");
  WormTrack unequal = t;
  unequal.x_mm[5].pop_back();
  expect_rejected(unequal, "x shorter than y");
  WormTrack short_cx = t;
  short_cx.cx_mm.pop_back();
  short_cx.cy_mm.pop_back();
  expect_rejected(short_cx, "cx/cy shorter than t");
  std::ofstream(file) << "{\"units\": {\"t\": \"s\", \"x\": \"mm\"}, \"data\": []}";
  EXPECT_EQ(CheckWcon(file), 1) << "no unit for y";
  std::ofstream(file) << "{\"units\": {\"t\": \"s\", \"x\": \"mm\", \"y\": \"mm\"}, \"owval\": 1, "
                         "\"data\": {\"id\": \"1\", \"t\": [0], \"x\": [[1]], \"y\": [[2]]}}";
  EXPECT_EQ(CheckWcon(file), 1) << "custom key without @";
  fs::remove(file);
}

TEST(Wcon, RoundTripGivesTheSameTrackAndTheSameKinematics) {
  if (!Worm()) GTEST_SKIP();
  const fs::path file = Temp("roundtrip.wcon");
  const WormTrack track = WormTrackOfReference();
  WriteWcon(track, file);
  const WormTrack back = ReadWcon(file);
  EXPECT_EQ(back.id, track.id);
  EXPECT_EQ(back.time_s, track.time_s);
  EXPECT_EQ(back.x_mm, track.x_mm);
  EXPECT_EQ(back.y_mm, track.y_mm);
  EXPECT_EQ(back.cx_mm, track.cx_mm);
  EXPECT_EQ(back.cy_mm, track.cy_mm);
  EXPECT_EQ(back.software_settings, track.software_settings);
  const Report from_wcon = Analyse(LoadSkeletons(file));
  const Report from_trajectory = Analyse(SkeletonsFromTrajectory(*Worm()));
  EXPECT_EQ(from_wcon.ToJson(), from_trajectory.ToJson());
  std::printf("%s", from_trajectory.ToText().c_str());
  fs::remove(file);
}

TEST(Wcon, ReaderRefusesBrokenFilesNamingTheField) {
  const fs::path file = Temp("broken.wcon");
  auto message = [&](const std::string& text) -> std::string {
    std::ofstream(file) << text;
    try {
      ReadWcon(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_NE(message("{\"data\": []}").find("units"), std::string::npos);
  EXPECT_NE(message("{\"units\": {\"t\": \"s\", \"x\": \"mm\", \"y\": \"furlong\"}, \"data\": "
                    "[]}")
                .find("units.y"),
            std::string::npos);
  EXPECT_NE(message("{\"units\": {\"t\": \"s\", \"x\": \"mm\", \"y\": \"mm\"}, \"data\": {\"id\": "
                    "\"1\", \"t\": [0, 1], \"x\": [[1, 2], [1]], \"y\": [[1, 2], [1, 2]]}}")
                .find("equal in length"),
            std::string::npos);
  EXPECT_NE(message("{\"units\": {\"t\": \"s\", \"x\": \"mm\", \"y\": \"mm\"}, \"data\": {\"id\": "
                    "\"1\", \"t\": [1, 0], \"x\": [[1], [1]], \"y\": [[1], [1]]}}")
                .find("increase"),
            std::string::npos);
  EXPECT_NE(message("{not json").find("not valid JSON"), std::string::npos);
  // Units are converted, unknown keys ignored, origins applied.
  std::ofstream(file)
      << "{\"units\": {\"t\": \"ms\", \"x\": \"um\", \"y\": \"mm\", \"ox\": \"um\", "
         "\"oy\": \"mm\"}, \"@X\": 5, \"data\": [{\"id\": \"7\", \"t\": [0, 500], "
         "\"ox\": [100, 100], \"oy\": [0, 0], \"x\": [[1000], [2000]], "
         "\"y\": [[1], [2]], \"@X\": [1, 2]}]}";
  const WormTrack t = ReadWcon(file);
  EXPECT_EQ(t.id, "7");
  EXPECT_EQ(t.time_s, (std::vector<double>{0, 0.5}));
  EXPECT_FLOAT_EQ(t.x_mm[1][0], 2.1f);
  EXPECT_FLOAT_EQ(t.y_mm[1][0], 2.f);
  fs::remove(file);
}

// Every time point WconReader gives, as a track, and its size() said before the first.
WormTrack ReadTimePoints(const fs::path& file) {
  WconReader points(file);
  const std::size_t size = points.size();
  WormTrack t;
  WconTimePoint p;
  while (points.Next(&p)) AppendTimePoint(p, points.has_centroid(), &t);
  EXPECT_EQ(t.time_s.size(), size);
  return t;
}

void ExpectSameTimePoints(const WormTrack& a, const WormTrack& b) {
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.x_mm, b.x_mm);
  EXPECT_EQ(a.y_mm, b.y_mm);
  EXPECT_EQ(a.cx_mm, b.cx_mm);
  EXPECT_EQ(a.cy_mm, b.cy_mm);
}

// The WCON read time point by time point (SAX, arrays spooled) gives the values written, whatever
// the order of a record's keys, and refuses what a WCON reader must.
TEST(Wcon, TimePointsReaderGivesTheWrittenValuesAndRefusals) {
  const fs::path file = Temp("time_points.wcon");
  if (Worm()) {  // owval's own WCON of the 0.6 s run
    const WormTrack written = TrackFromTrajectory(*Worm());
    WriteWcon(written, file);
    ExpectSameTimePoints(ReadTimePoints(file), written);
  }
  // Keys in another order (x, cx before t), two records of the id, another id between them,
  // units converted, origins applied, a single point given as a number, unknown keys ignored.
  std::ofstream(file)
      << "{\"data\": [{\"x\": [[1000, 3000], [2000, 1000]], \"cy\": [1, 2], \"cx\": [5, 6], "
         "\"y\": [[1, 2], [2, 3]], \"id\": \"7\", \"t\": [0, 500], \"ox\": [100, 100], "
         "\"@X\": {\"t\": [9]}}, {\"id\": \"8\", \"t\": [0], \"x\": [[1]], \"y\": [[1]]}, "
         "{\"id\": \"7\", \"t\": [600], \"x\": [4000], \"y\": [5], \"cx\": [7], \"cy\": [8]}], "
         "\"units\": {\"t\": \"ms\", \"x\": \"um\", \"y\": \"mm\", \"cx\": \"um\", \"cy\": "
         "\"mm\"}}";
  const WormTrack foreign = ReadTimePoints(file);
  ExpectSameTimePoints(foreign, ReadWcon(file));
  ASSERT_EQ(foreign.time_s.size(), 3u);
  EXPECT_EQ(foreign.time_s, (std::vector<double>{0, 0.5, 0.6}));
  EXPECT_EQ(foreign.y_mm, (std::vector<std::vector<float>>{{1, 2}, {2, 3}, {5}}));
  EXPECT_FLOAT_EQ(foreign.x_mm[0][1], 3.1f);
  EXPECT_DOUBLE_EQ(foreign.cx_mm[1], 0.106);
  EXPECT_EQ(foreign.x_mm[2].size(), 1u);
  auto refusal = [&](const std::string& text) -> std::string {
    std::ofstream(file) << text;
    try {
      ReadTimePoints(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  const std::string units = "{\"units\": {\"t\": \"s\", \"x\": \"mm\", \"y\": \"mm\"}, ";
  EXPECT_NE(refusal("{\"data\": []}").find("units"), std::string::npos);
  EXPECT_NE(refusal("{\"units\": {\"t\": \"s\", \"x\": \"mm\", \"y\": \"furlong\"}, \"data\": "
                    "[{\"id\": \"1\", \"t\": [0], \"x\": [[1]], \"y\": [[1]]}]}")
                .find("units.y: unsupported unit"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": {\"id\": \"1\", \"t\": [0, 1], \"x\": [[1, 2], [1]], "
                            "\"y\": [[1, 2], [1, 2]]}}")
                .find("data[0].x/y[1]: x and y must be equal in length"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": {\"id\": \"1\", \"t\": [1, 0], \"x\": [[1], [1]], "
                            "\"y\": [[1], [1]]}}")
                .find("data: t: frame 1's time 0 s is not after frame 0's 1 s"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": {\"id\": \"1\", \"t\": [0, null], \"x\": [[1], [1]], "
                            "\"y\": [[1], [1]]}}")
                .find("data[0].t: expected numbers"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": {\"id\": \"1\", \"t\": [0, 1], \"x\": [[1]], "
                            "\"y\": [[1], [1]]}}")
                .find("data[0].x/y: expected one array per time point"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": {\"id\": \"1\", \"t\": [0], \"x\": [[1]], \"y\": [[1]], "
                            "\"cx\": [0]}}")
                .find("data[0].cx/cy: must come in pairs"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": {\"id\": 1, \"t\": [0], \"x\": [[1]], \"y\": [[1]]}}")
                .find("data[0].id: expected a string"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": [{\"t\": [0], \"x\": [[1]], \"y\": [[1]]}]}")
                .find("data[0]: expected a record with id, t, x and y"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": [{\"id\": \"1\", \"t\": [0], \"x\": [[1e300]], "
                            "\"y\": [[1]]}]}")
                .find("out of range"),
            std::string::npos);
  EXPECT_NE(refusal(units + "\"data\": [{\"id\": \"1\", \"t\": [1e400], \"x\": [[1]], "
                            "\"y\": [[1]]}]}"),
            "accepted");
  EXPECT_EQ(refusal("{not json"),
            file.string() +
                ":1:3: not valid JSON: syntax error while parsing object key "
                "- invalid literal; last read: '{no'; expected string literal");
  fs::remove(file);
}

TEST(Wcon, ATrajectoryWithoutAWormIsRefusedNamingTheFile) {
  const fs::path sprig = owval::testing::kBundledOneSprig;
  try {
    LoadSkeletons(sprig);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), sprig.string());
    EXPECT_NE(std::string(e.what()).find("no worm body"), std::string::npos);
  }
}

// "kinematics need at least 2 frames with one skeleton each" and "skeleton needs at least 2
// points" named no file: a WCON of one time point, or of one point a time (a centroid track).
TEST(Wcon, KinematicsOfTooFewFramesOrPointsNameTheFile) {
  const fs::path file = Temp("too_little.wcon");
  auto message = [&](const std::string& t, const std::string& x) -> std::string {
    std::ofstream(file) << R"({"units": {"t": "s", "x": "mm", "y": "mm"}, "data": {"id": "1", )"
                        << "\"t\": " << t << ", \"x\": " << x << ", \"y\": " << x << "}}";
    try {
      LoadSkeletons(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(message("[0]", "[[0, 1]]"),
            file.string() + ": holds 1 frame(s): kinematics need at least 2 frames");
  EXPECT_EQ(message("[0, 1]", "[[0, 1], [2]]"),
            file.string() +
                ": frame 1's skeleton has 1 point(s): kinematics need at least 2 midline points a "
                "frame");
  EXPECT_EQ(message("[0, 1]", "[[0, 1], [2, 3]]"), "accepted");
  fs::remove(file);
}

template <typename T>
void WriteRaw(const fs::path& path, const std::vector<T>& values) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

TEST(OmeZarr, ZarrPythonReadsBackEveryValue) {
  if (!Worm() || !fs::exists(kPython)) GTEST_SKIP() << "needs the worm reference and python3";
  const Trajectory& t = *Worm();
  const fs::path store = Temp("worm.zarr");
  ZarrWriteOptions options;  // 16 frames per chunk: 200 frames end in a partial chunk
  WriteOmeZarr(t, store, options);
  std::vector<float> um(t.positions.size());
  const float to_um = static_cast<float>(options.simulation_scale_m * 1e6);
  for (std::size_t i = 0; i < um.size(); ++i) um[i] = t.positions[i] * to_um;
  WriteRaw(Temp("positions.f32"), um);
  WriteRaw(Temp("types.f32"), t.type);
  WriteRaw(Temp("time.f64"), t.time_s);
  EXPECT_NEAR(um[2], t.positions[2] * 7.4, 1e-3 * um[2]);  // z of particle 0, in um
  const std::string args = (kTests / "check_zarr.py").string() + " " + store.string() + " " +
                           Temp("positions.f32").string() + " " + Temp("types.f32").string() + " " +
                           Temp("time.f64").string() + " " + std::to_string(t.frame_count()) + " " +
                           std::to_string(t.particle_count());
  EXPECT_EQ(Python(args), 0) << args;
  um[12345] += 1.f;  // the check must notice one changed value
  WriteRaw(Temp("positions.f32"), um);
  EXPECT_EQ(Python(args), 1);
  for (const char* f : {"positions.f32", "types.f32", "time.f64"}) fs::remove(Temp(f));
  fs::remove_all(store);
}

// owval's reader reads back every value, and the store must describe the trajectory beside it:
// the reversed run's store beside the run disagrees at every frame (200: no middle frame)
// (side_files.hpp; ci's quick-test and validate use this).
TEST(OmeZarr, OwvalsReaderReadsBackEveryValueAndNamesAStoreOfAnotherRun) {
  if (!Worm()) GTEST_SKIP() << "needs the worm reference";
  const Trajectory& t = *Worm();
  const fs::path store = Temp("worm.zarr");
  WriteOmeZarr(t, store);
  OmeZarrReader zarr(store);
  ASSERT_EQ(zarr.frame_count(), t.frame_count());
  EXPECT_EQ(zarr.time_s(), t.time_s);
  EXPECT_EQ(zarr.type(), t.type);
  const float to_um = static_cast<float>(ZarrWriteOptions{}.simulation_scale_m * 1e6);
  std::size_t unequal = 0;
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    const float* um = zarr.FrameMicrometres(f);
    for (std::size_t k = 0; k < t.particle_count() * 3; ++k)
      unequal += um[k] != t.position(f, 0)[k] * to_um;
  }
  EXPECT_EQ(unequal, 0u);
  const auto frames = MemoryFrameSource(t);
  const TrackAgreement same = CompareWithTrajectory(zarr, *frames);
  EXPECT_TRUE(same.agrees) << same.detail;
  EXPECT_LT(same.worst_fraction_of_allowance, 0.01);
  Trajectory reversed = t;
  const std::size_t n = t.particle_count() * 3;
  for (std::size_t f = 0; f < t.frame_count(); ++f)
    std::copy_n(t.position(t.frame_count() - 1 - f, 0), n, reversed.position(f, 0));
  fs::remove_all(store);
  WriteOmeZarr(reversed, store);
  OmeZarrReader other(store);
  const TrackAgreement a = CompareWithTrajectory(other, *frames);
  EXPECT_FALSE(a.agrees);
  EXPECT_EQ(a.detail.rfind("200 frames; 200 disagree", 0), 0u) << a.detail;
  fs::remove_all(store);
}

// The store says its positions' unit and the scale they were converted at; the reader applies
// the unit and the comparison refuses another scale, rather than assuming Sibernetic's µm.
TEST(OmeZarr, OwvalsReaderAppliesTheStoresUnitAndRefusesAnotherScale) {
  if (!Worm()) GTEST_SKIP() << "needs the worm reference";
  Trajectory t = *Worm();
  t.time_s.resize(20);  // 20 frames keep it short
  t.positions.resize(20 * t.particle_count() * 3);
  const auto frames = MemoryFrameSource(t);
  const fs::path store = Temp("scaled.zarr");
  WriteOmeZarr(t, store);
  const fs::path units = store / "body/positions/.zattrs";
  const auto label = [&](const std::string& unit) {
    std::ofstream(units) << "{\"units\": " << unit << "}";
  };
  const auto error = [&](const std::function<void()>& f) -> std::string {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  label("\"mm\"");  // µm values labelled mm: read as mm, they are 1000 times the worm
  OmeZarrReader mm(store);
  const float to_um = static_cast<float>(ZarrWriteOptions{}.simulation_scale_m * 1e6);
  EXPECT_FLOAT_EQ(mm.FrameMicrometres(3)[5], t.position(3, 0)[5] * to_um * 1000);
  const TrackAgreement labelled_mm = CompareWithTrajectory(mm, *frames);
  EXPECT_FALSE(labelled_mm.agrees);
  EXPECT_GT(labelled_mm.worst_fraction_of_allowance, 100) << labelled_mm.detail;
  label("\"um\"");
  OmeZarrReader um(store);
  EXPECT_TRUE(CompareWithTrajectory(um, *frames).agrees);
  label("\"furlong\"");
  EXPECT_NE(
      error([&] { OmeZarrReader{store}; }).find(units.string() + ": units: expected a length"),
      std::string::npos);
  fs::remove_all(store);
  ZarrWriteOptions ten_micrometres;
  ten_micrometres.simulation_scale_m = 1e-5;
  WriteOmeZarr(t, store, ten_micrometres);
  OmeZarrReader scaled(store);
  EXPECT_EQ(scaled.simulation_scale_m(), 1e-5);
  EXPECT_EQ(error([&] { CompareWithTrajectory(scaled, *frames); }),
            (store / ".zattrs").string() +
                ": @owval.simulation_scale_m: 1e-05 m per configuration unit, but the "
                "trajectory's are Sibernetic's 7.39999905e-06 m");
  fs::remove_all(store);
}

// A store whose .zarray claims a chunk of 1e15 frames is refused by the memory budget (bad
// input naming the chunk file), not allocated.
TEST(OmeZarr, OwvalsReaderHoldsAClaimedChunkToTheMemoryBudget) {
  if (!Worm()) GTEST_SKIP() << "needs the worm reference";
  const fs::path store = Temp("huge_chunk.zarr");
  WriteOmeZarr(*Worm(), store);
  const fs::path meta = store / "body/positions/.zarray";
  nlohmann::json m = nlohmann::json::parse(std::ifstream(meta));
  m["chunks"][0] = 1000000000000000.0;
  std::ofstream(meta) << m.dump();
  OmeZarrReader zarr(store);
  try {
    zarr.FrameMicrometres(0);
    ADD_FAILURE() << "a 1e15-frame chunk was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("chunk needs"), std::string::npos) << e.what();
  }
  fs::remove_all(store);
}

}  // namespace
}  // namespace owval::kinematics
