#include "log_lines.hpp"

#include "owval/base/errors.hpp"
#include "owval/base/input_file.hpp"

namespace owval::kinematics {

LogLines::LogLines(std::filesystem::path path, std::string expected)
    : path_(std::move(path)), expected_(std::move(expected)) {
  RequireInputFile(path_);  // before gzopen(): a FIFO would block it
  file_ = gzopen(path_.c_str(), "rb");
  if (!file_) throw InputError(path_.string(), 0, "cannot open");
}

LogLines::~LogLines() { gzclose(file_); }

// gzread, not gzgets: gzgets' C string ended at a NUL byte, so a line starting with one was read
// as "" and its last character read before the string (UBSan, fuzz_side_files).
bool LogLines::Next(std::string* line) {
  line->clear();
  while (true) {
    if (at_ == block_.size() && !Refill()) break;
    const std::size_t newline = block_.find('\n', at_);
    const std::size_t end = newline == std::string::npos ? block_.size() : newline + 1;
    line->append(block_, at_, end - at_);
    at_ = end;
    if (newline != std::string::npos) break;
    if (line->size() > kMaxLogLineBytes)
      throw InputError(
          path_.string(), number_ + 1,
          "line longer than " + std::to_string(kMaxLogLineBytes) + " bytes; expected " + expected_);
  }
  int error = Z_OK;
  gzerror(file_, &error);
  if (error != Z_OK && error != Z_STREAM_END)
    throw InputError(path_.string(), number_ + 1, "corrupt gzip data");
  if (line->empty()) return false;
  ++number_;
  return true;
}

// The next block of the (decompressed) file; false at its end or on an error (gzerror's).
bool LogLines::Refill() {
  block_.resize(std::size_t{1} << 14);
  const int got = gzread(file_, block_.data(), static_cast<unsigned>(block_.size()));
  block_.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
  at_ = 0;
  return got > 0;
}

}  // namespace owval::kinematics
