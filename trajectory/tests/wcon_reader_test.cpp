// The one WCON reader (WconReader, worm_formats.hpp): the metadata kept while the time points
// stream, the file parsed once (Rewind), and JSON that does not parse named by line and column
// (counted while streaming, across the reader's 64 KiB buffers).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/testing/scratch_directory.hpp"
#include "owval/testing/test_files.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using testing::ScratchFile;

fs::path Written(const std::string& name, const std::string& text) {
  const fs::path path = ScratchFile(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// `points` time points of a 99-point skeleton with a centroid: owval's WCON text of it is
// several 64 KiB buffers long.
WormTrack Track(std::size_t points) {
  WormTrack t;
  t.id = "w1";
  t.software_version = "9.9";
  t.software_settings = {{"backend", "xpbd"}, {"steps", {1, 2, 3}}};
  t.owval = {{"simulation_scale_m", 7.4e-6}, {"nested", {{"empty", json::array()}}}};
  for (std::size_t i = 0; i < points; ++i) {
    t.time_s.push_back(0.003 * double(i));
    std::vector<float> x, y;
    for (int k = 0; k < 99; ++k) {
      x.push_back(0.01f * float(k) + 1e-4f * float(i));
      y.push_back(-0.02f * float(k));
    }
    t.x_mm.push_back(x);
    t.y_mm.push_back(y);
    t.cx_mm.push_back(0.5 + 1e-3 * double(i));
    t.cy_mm.push_back(-1);
  }
  return t;
}

TEST(WconReader, KeepsTheMetadataWhileTheTimePointsStream) {
  const WormTrack written = Track(300);
  const fs::path path = ScratchFile("metadata.wcon");
  WriteWcon(written, path);
  WconReader reader(path);
  EXPECT_EQ(reader.head().id, "w1");
  EXPECT_EQ(reader.head().software_version, "9.9");
  EXPECT_EQ(reader.head().software_settings, written.software_settings);
  EXPECT_EQ(reader.head().owval, written.owval);
  EXPECT_TRUE(reader.head().time_s.empty());
  EXPECT_EQ(reader.size(), 300u);
  const WormTrack back = ReadWcon(path);
  EXPECT_EQ(back.software_settings, written.software_settings);
  EXPECT_EQ(back.owval, written.owval);
  EXPECT_EQ(back.time_s, written.time_s);
  EXPECT_EQ(back.x_mm, written.x_mm);
  EXPECT_EQ(back.cx_mm, written.cx_mm);
}

// Where another producer puts them: "@owval" after the data, metadata before the units, keys the
// reader does not know around them; a later key of the same name replaces an earlier one, as in
// json::parse.
TEST(WconReader, KeepsTheMetadataInAnyOrderAsAWholeDocumentParseDoes) {
  const std::string text = R"({"metadata": {"lab": {"x": [1]}, "software": {"settings": [1, {"b":
      null, "c": [true, "s", -2, 3.5]}], "version": "0.1", "name": "other"}},
    "units": {"t": "s", "x": "mm", "y": "mm"}, "@owval": {"old": 1},
    "data": [{"id": "7", "t": [0], "x": [[1]], "y": [[2]]}],
    "@owval": {"a": {"b": [[], {}]}, "n": 18446744073709551615}})";
  const fs::path path = Written("order.wcon", text);
  const json whole = json::parse(text);
  const WormTrack t = ReadWcon(path);
  EXPECT_EQ(t.id, "7");
  EXPECT_EQ(t.software_version, "0.1");
  EXPECT_EQ(t.software_settings, whole["metadata"]["software"]["settings"]);
  EXPECT_EQ(t.owval, whole["@owval"]);
  EXPECT_EQ(t.owval["n"].get<std::uint64_t>(), 18446744073709551615u);
  // Without metadata: what a track holds by default.
  const WormTrack bare =
      ReadWcon(Written("bare.wcon", R"({"units": {"t": "s", "x": "mm", "y": "mm"}, "metadata": 5,
                      "data": {"id": "1", "t": [0], "x": [[1]], "y": [[2]]}})"));
  EXPECT_EQ(bare.software_version, "");
  EXPECT_EQ(bare.software_settings, json::object());
  EXPECT_EQ(bare.owval, json::object());
}

TEST(WconReader, RewindGivesTheSameTimePointsWithoutParsingAgain) {
  const fs::path path = ScratchFile("rewind.wcon");
  WriteWcon(Track(50), path);
  WconReader reader(path);
  WormTrack first, second;
  WconTimePoint p;
  while (reader.Next(&p)) AppendTimePoint(p, reader.has_centroid(), &first);
  fs::remove(path);  // the spools hold what Next reads: the file is not read again
  reader.Rewind();
  while (reader.Next(&p)) AppendTimePoint(p, reader.has_centroid(), &second);
  EXPECT_EQ(first.time_s.size(), 50u);
  EXPECT_EQ(second.time_s, first.time_s);
  EXPECT_EQ(second.x_mm, first.x_mm);
  EXPECT_EQ(second.y_mm, first.y_mm);
  EXPECT_EQ(second.cx_mm, first.cx_mm);
  EXPECT_EQ(second.cy_mm, first.cy_mm);
}

// A token no JSON has, on line 4.
TEST(WconSyntax, ABadTokenIsNamedByItsLineAndColumn) {
  const fs::path path = Written("bad_token.wcon",
                                "{\"units\": {\"t\": \"s\", \"x\": \"mm\", \"y\": "
                                "\"mm\"},\n \"data\": [{\"id\": \"1\",\n   "
                                "\"t\": [0, 1],\n   \"x\": [[0, 1], [0, 1]], "
                                "\"y\": [[0, 0], [0, tru]]}]}\n");
  // Column 48: the ']' after "tru", where "true" cannot go on.
  EXPECT_EQ(testing::InputErrorOf([&] { WconReader reader(path); }),
            path.string() +
                ":4:48: not valid JSON: syntax error while parsing value - invalid "
                "literal; last read: '0, tru]'");
}

// The line and column of byte `index` (from 0) of `text`, counted here on the whole text.
std::pair<std::size_t, std::size_t> LineAndColumn(const std::string& text, std::size_t index) {
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < index; ++i)
    if (text[i] == '\n') ++line, line_start = i + 1;
  return {line, index - line_start + 1};
}

// A bad character deep in a file several buffers long (just after a newline, across a buffer's
// end, in the last line): the line and column counted while streaming are the text's.
TEST(WconSyntax, AnErrorDeepInALongFileIsNamedByItsLineAndColumn) {
  const std::string good = WconText(Track(300));
  ASSERT_GT(good.size(), 4u * 65536);
  const std::size_t after_newline = good.find('\n', 3 * 65536) + 1;
  for (std::size_t at : {std::size_t(65535), std::size_t(65536), std::size_t(65537), after_newline,
                         good.size() / 2, good.rfind(']') - 3}) {
    std::string text = good;
    text[at] = '#';
    const fs::path path = Written("deep.wcon", text);
    const auto [line, column] = LineAndColumn(text, at);
    const std::string error = testing::InputErrorOf([&] { WconReader reader(path); });
    EXPECT_EQ(error.rfind(path.string() + ":" + std::to_string(line) + ":" +
                              std::to_string(column) + ": not valid JSON: syntax error",
                          0),
              0u)
        << "# at byte " << at << " (line " << line << ", column " << column << "): " << error;
  }
}

// A file cut short (a copy interrupted, a disk full): the end of the file, as line and column.
TEST(WconSyntax, ATruncatedFileIsNamedByWhereItEnds) {
  const std::string good = WconText(Track(300));
  for (std::size_t length :
       {good.find(',', good.size() * 2 / 3) + 1, good.find('\n', good.size() / 3) + 1}) {
    const std::string text = good.substr(0, length);
    const fs::path path = Written("truncated.wcon", text);
    const auto [line, column] = LineAndColumn(text, length);  // the byte after the last
    EXPECT_EQ(testing::InputErrorOf([&] { WconReader reader(path); })
                  .rfind(path.string() + ":" + std::to_string(line) + ":" + std::to_string(column) +
                             ": not valid JSON: syntax error while parsing ",
                         0),
              0u)
        << "cut at " << length;
    EXPECT_NE(testing::InputErrorOf([&] { ReadWcon(path); }).find("unexpected end of input"),
              std::string::npos);
  }
  EXPECT_EQ(testing::InputErrorOf([&] { ReadWcon(Written("empty.wcon", "")); }),
            ScratchFile("empty.wcon").string() +
                ":1:1: not valid JSON: syntax error while parsing value - unexpected end of input; "
                "expected '[', '{', or a literal");
}

}  // namespace
}  // namespace owval
