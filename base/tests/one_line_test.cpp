#include "owval/base/one_line.hpp"

#include <gtest/gtest.h>

#include <string>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

bool PrintableAscii(const std::string& s) {
  for (char c : s)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) return false;
  return true;
}

TEST(OneLine, LeavesAShortPlainMessageAlone) {
  EXPECT_EQ(OneLine("a.txt:3: expected x, found 'q'"), "a.txt:3: expected x, found 'q'");
}

TEST(OneLine, EscapesNewlinesAndControlBytes) {
  EXPECT_EQ(OneLine("a\nb\rc\td\x01\xff"), "a\\nb\\rc\\td\\x01\\xff");
}

TEST(OneLine, CutsAFiveMegabyteTokenToItsHeadAndTail) {
  const std::string token = "x" + std::string(5u << 20, '9') + "y";
  const std::string line = OneLine("found '" + token + "' here");
  EXPECT_LE(line.size(), kMaxMessageChars);
  EXPECT_NE(line.find("..."), std::string::npos);
  EXPECT_NE(line.find("' here"), std::string::npos);
  EXPECT_EQ(line.rfind("found 'x", 0), 0u);
}

TEST(OneLine, CutsALongMessageAt300CharactersWithoutSplittingAnEscape) {
  std::string many;
  for (int i = 0; i < 400; ++i) many += "\x01 ";
  const std::string line = OneLine(many);
  EXPECT_LE(line.size(), kMaxMessageChars);
  EXPECT_EQ(line.substr(line.size() - 3), "...");
  EXPECT_TRUE(PrintableAscii(line));
  const std::size_t slash = line.rfind('\\');
  EXPECT_EQ(line.substr(slash, 4), "\\x01");
}

TEST(OneLine, InputErrorMessagesAreOneShortPrintableLine) {
  const InputError e("cfg.txt", 7, "unknown section '[" + std::string(100000, '\n') + "]'");
  const std::string what = e.what();
  EXPECT_LE(what.size(), kMaxMessageChars);
  EXPECT_TRUE(PrintableAscii(what));
  EXPECT_EQ(what.rfind("cfg.txt:7: unknown section", 0), 0u);
  EXPECT_EQ(e.file(), "cfg.txt");
}

}  // namespace
}  // namespace owval
