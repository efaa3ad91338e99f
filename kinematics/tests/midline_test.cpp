#include "owval/kinematics/midline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "../../trajectory/src/gzip.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::kinematics {
namespace {
namespace fs = std::filesystem;

const fs::path kWorm = fs::path(OWVAL_SHARED_DIR) / "reference/worm_alone_0.6s";

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t tab; (tab = line.find('\t', start)) != std::string::npos; start = tab + 1)
    fields.push_back(line.substr(start, tab - start));
  fields.push_back(line.substr(start));
  return fields;
}

TEST(Midline, BinsFollowSiberneticsSubTypeCodes) {
  EXPECT_EQ(MidlineBin(2.1051f), 52);  // the 3e-7 nudge puts 2.10509992f in bin 52
  EXPECT_EQ(MidlineBin(2.1050f), 51);
  EXPECT_EQ(MidlineBin(2.1149f), 150);
  EXPECT_EQ(MidlineBin(2.2051f), 52);
  EXPECT_EQ(MidlineBin(2.1f), 1);
  EXPECT_EQ(MidlineBin(2.0f), 0);
  EXPECT_EQ(MidlineBin(2.3f), 0);
  EXPECT_EQ(MidlineBin(1.1f), 0);
}

TEST(Midline, PrintedSlotsAreBins51To149) {
  EXPECT_EQ(PrintedBinSlot(2.1050f), 0);   // bin 51
  EXPECT_EQ(PrintedBinSlot(2.1051f), 1);   // bin 52
  EXPECT_EQ(PrintedBinSlot(2.1148f), 98);  // bin 149
  EXPECT_EQ(PrintedBinSlot(2.1149f), -1);  // bin 150: summed by Sibernetic, never printed
  EXPECT_EQ(PrintedBinSlot(2.1049f), -1);  // bin 50
  EXPECT_EQ(PrintedBinSlot(1.1f), -1);     // liquid
}

TEST(Midline, LineLayoutIsSiberneticsWithAxisSwap) {
  Midline m;
  m.x_mm[0] = 1.f;
  m.y_mm[0] = 2.f;
  m.z_mm[0] = 3.f;
  const std::vector<std::string> f = Fields(FormatWormMotionLine(m, 150, 2e-5));
  ASSERT_EQ(f.size(), 304u);  // as README: 304 TAB-separated fields, the last one "\n"
  EXPECT_EQ(f[0], "3.000000e-03");
  EXPECT_EQ(f[1], "X:");
  EXPECT_EQ(f[2], "3.000000e+00");  // X block = mean z
  EXPECT_EQ(f[101], "");            // the value TAB followed by "\tY:\t"
  EXPECT_EQ(f[102], "Y:");
  EXPECT_EQ(f[103], "1.000000e+00");  // Y block = mean x
  EXPECT_EQ(f[204], "2.000000e+00");  // Z block = mean y
  EXPECT_EQ(f[303], "\n");
}

// From Sibernetic's printed positions (6 significant digits) the means can differ from
// Sibernetic's (computed from the device's float positions) in the 7th printed digit, never more
// than the printed positions' rounding allows: half a unit of the 6th digit of the position.
TEST(Midline, FromSiberneticsPrintedPositionsAgreesWithItsLogToSixDigits) {
  if (!fs::exists(kWorm)) GTEST_SKIP() << "no " << kWorm;
  TextReadOptions quiet;
  quiet.quiet = true;
  const Trajectory t = ReadTrajectory(kWorm / "position_buffer.txt.gz", quiet);
  ASSERT_TRUE(IsWorm(t));
  const std::vector<std::string> ours = Lines(WormMotionLog(t));
  const std::vector<std::string> theirs = Lines(owval::internal::Gunzip(
      ReadWholeFile(kWorm / "worm_motion_log.txt.gz"), "worm_motion_log.txt.gz"));
  ASSERT_EQ(ours.size(), theirs.size());
  std::size_t values = 0, equal = 0;
  double worst = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    const std::vector<std::string> a = Fields(ours[i]), b = Fields(theirs[i]);
    ASSERT_EQ(a.size(), b.size()) << "line " << i;
    EXPECT_EQ(a[0], b[0]) << "time of line " << i;
    for (std::size_t k = 2; k < a.size(); ++k) {
      if (a[k] == "Y:" || a[k] == "Z:" || a[k].empty()) {
        EXPECT_EQ(a[k], b[k]);
        continue;
      }
      ++values;
      equal += a[k] == b[k];
      const double x = std::stod(a[k]), y = std::stod(b[k]);
      worst = std::max(worst, std::abs(x - y) / std::max(std::abs(y), 1e-30));
    }
  }
  EXPECT_EQ(values, 200u * 297u);
  EXPECT_LT(worst, 5e-6) << equal << " of " << values << " printed values identical";
  std::printf("midline from printed positions: %zu of %zu values identical, worst relative %.2e\n",
              equal, values, worst);
}

}  // namespace
}  // namespace owval::kinematics
