#include "owval/base/input_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/mapped_file.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/testing/scratch_directory.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;

fs::path Scratch(const std::string& name) { return owval::testing::TestScratch() / name; }

std::string MessageOf(void (*read)(const fs::path&), const fs::path& path) {
  try {
    read(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void Map(const fs::path& p) { MappedFile file(p); }
void ReadAll(const fs::path& p) { ReadWholeFile(p); }

// A FIFO with no writer blocks open() forever: the readers must refuse it without opening it.
TEST(RequireInputFile, RefusesAFifoWithoutHanging) {
  const fs::path fifo = Scratch("pipe");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(MessageOf(&Map, fifo).find("FIFO"), std::string::npos);
  EXPECT_NE(MessageOf(&ReadAll, fifo).find("FIFO"), std::string::npos);
  fs::remove(fifo);
}

TEST(RequireInputFile, RefusesADirectoryNamingIt) {
  const fs::path dir = Scratch("adir");
  fs::create_directories(dir);
  const std::string message = MessageOf(&Map, dir);
  EXPECT_NE(message.find("adir: is a directory"), std::string::npos) << message;
  EXPECT_NE(MessageOf(&ReadAll, dir).find("directory"), std::string::npos);
}

TEST(RequireInputFile, AcceptsARegularFile) {
  const fs::path file = Scratch("plain.txt");
  std::ofstream(file) << "1\n";
  EXPECT_NO_THROW(RequireInputFile(file));
  EXPECT_EQ(ReadWholeFile(file), "1\n");
}

TEST(MemoryBudget, RefusesAnAllocationOverTheBudgetNamingFileAndField) {
  SetMemoryBudgetBytes(1000);
  try {
    CheckAllocation(1001, "t.h5", "/time");
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "t.h5: /time needs 1001 bytes, more than the memory budget of 1000 bytes "
              "(--max-memory)");
  }
  EXPECT_NO_THROW(CheckAllocation(1000, "t.h5", "/time"));
  SetMemoryBudgetBytes(0);
  EXPECT_GT(MemoryBudgetBytes(), 1000u);
  EXPECT_EQ(SaturatingProduct(std::size_t(1) << 40, std::size_t(1) << 40), SIZE_MAX);
}

}  // namespace
}  // namespace owval
