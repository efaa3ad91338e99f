#pragma once
// Sibernetic's text logs (worm_motion_log.txt, muscles_activity_buffer.txt), plain or
// gzip-compressed, a line at a time: gzopen reads a plain file as it is (Sibernetic's logs are
// kept .gz). Memory: one 16 KiB block and one line, and a line is refused past 1 MiB, so a small
// gzip bomb with no newline is not read into one string.
#include <cstddef>
#include <filesystem>
#include <string>

#include <zlib.h>

namespace owval::kinematics {

constexpr std::size_t kMaxLogLineBytes = std::size_t{1} << 20;

class LogLines {
 public:
  // `expected`: what a line holds, for the messages of the InputErrors thrown here.
  LogLines(std::filesystem::path path, std::string expected);
  ~LogLines();
  LogLines(const LogLines&) = delete;
  LogLines& operator=(const LogLines&) = delete;

  // The next line (its newline kept, if it has one) into `line`; false at the end of the file.
  // InputError naming the file and line when it is longer than kMaxLogLineBytes or the gzip data
  // are corrupt.
  bool Next(std::string* line);
  std::size_t number() const { return number_; }  // the line Next returned last, from 1
  const std::filesystem::path& path() const { return path_; }

 private:
  bool Refill();

  std::filesystem::path path_;
  std::string expected_;
  gzFile file_;
  std::string block_;
  std::size_t at_ = 0, number_ = 0;  // at_: the next unread byte of block_
};

}  // namespace owval::kinematics
