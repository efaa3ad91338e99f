#pragma once
// The Sibernetic text parser's pieces shared by the whole-file reader (text_format.cpp) and the
// frame-by-frame one (text_stream.cpp), so that both accept and refuse exactly the same files.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::internal {

// A cursor over the file text that knows its line number, for error messages.
class TextCursor {
 public:
  // first_line: the line number of text's first line (a block of a file read in blocks).
  TextCursor(std::string_view text, const std::string& name, std::size_t first_line = 1)
      : p_(text.data()), end_(text.data() + text.size()), name_(name), line_(first_line) {}

  bool at_end() const { return p_ >= end_; }
  std::size_t line() const { return line_; }
  const std::string& name() const { return name_; }
  std::size_t offset(std::string_view text) const {
    return static_cast<std::size_t>(p_ - text.data());
  }

  [[noreturn]] void Fail(const std::string& what) const { throw InputError(name_, line_, what); }

  void SkipBlanks() {
    while (p_ < end_ && (*p_ == '\t' || *p_ == ' ')) ++p_;
  }

  // Parses one number; `what` names the expected field for the message.
  template <typename T>
  T Number(const char* what) {
    const T value = AnyNumber<T>(what);
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(value)) Fail(std::string(what) + " is not finite (NaN or Inf)");
    }
    return value;
  }

  // A particle's coordinate, x, y or z: a NaN or an infinity there is the record of a failed
  // simulation (NonFiniteTrajectoryError, exit 1), not a malformed file.
  float Coordinate(const char* what) {
    const float value = AnyNumber<float>(what);
    if (!std::isfinite(value))
      throw NonFiniteTrajectoryError(name_, line_,
                                     std::string(what) + " is not finite (NaN or Inf)");
    return value;
  }

  // Clinger's fast path for the plain decimals Sibernetic writes ("-17.535"): with at most 7
  // significant digits and 10 fraction digits, mantissa and power of ten are exact floats, so one
  // IEEE division gives the correctly rounded result, the same value std::from_chars returns.
  // Anything else (exponents, long mantissas, "nan") is left to from_chars.
  bool FastDecimal(float* out) {
    static constexpr float kPow10[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f,
                                       1e6f, 1e7f, 1e8f, 1e9f, 1e10f};
    const char* p = p_;
    const bool negative = p < end_ && *p == '-';
    if (negative) ++p;
    std::uint32_t mantissa = 0;
    int digits = 0, fraction = 0;
    const char* start = p;
    while (p < end_ && static_cast<unsigned>(*p - '0') < 10)
      mantissa = mantissa * 10 + static_cast<std::uint32_t>(*p++ - '0'), ++digits;
    if (p < end_ && *p == '.') {
      ++p;
      while (p < end_ && static_cast<unsigned>(*p - '0') < 10) {
        mantissa = mantissa * 10 + static_cast<std::uint32_t>(*p++ - '0');
        ++digits;
        ++fraction;
      }
    }
    if (digits == 0 || digits > 7 || fraction > 10 || p == start) return false;
    if (p < end_ && !IsSeparator(*p)) return false;
    const float magnitude = static_cast<float>(mantissa) / kPow10[fraction];
    *out = negative ? -magnitude : magnitude;
    p_ = p;
    return true;
  }

  void EndOfLine(const char* what) {
    SkipBlanks();
    if (p_ < end_ && *p_ == '\r') ++p_;
    if (p_ < end_ && *p_ != '\n') {
      const char* stop = p_;
      while (stop < end_ && *stop != '\n') ++stop;
      Fail(std::string("unexpected extra field after ") + what + ": '" + std::string(p_, stop) +
           "'");
    }
    if (p_ < end_) ++p_;
    ++line_;
  }

  void SkipEmptyTail() {
    while (p_ < end_ && (*p_ == '\n' || *p_ == '\r' || *p_ == ' ' || *p_ == '\t')) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
  }

 private:
  // One number, NaN and infinities included.
  template <typename T>
  T AnyNumber(const char* what) {
    SkipBlanks();
    T value{};
    if constexpr (std::is_same_v<T, float>) {
      if (FastDecimal(&value)) return value;
    }
    if (p_ >= end_ || *p_ == '\n' || *p_ == '\r')
      Fail(std::string("expected ") + what + ", found end of line");
    const char* start = p_;
    if (*p_ == '+') ++p_;  // from_chars rejects a leading '+', text writers may emit one
    auto [next, ec] = std::from_chars(p_, end_, value);
    if (ec != std::errc() || (next < end_ && !IsSeparator(*next))) {
      const char* stop = start;
      while (stop < end_ && !IsSeparator(*stop)) ++stop;
      Fail(std::string("expected ") + what + ", found '" + std::string(start, stop) + "'");
    }
    p_ = next;
    return value;
  }

  static bool IsSeparator(char c) { return c == '\t' || c == ' ' || c == '\n' || c == '\r'; }

  const char* p_;
  const char* end_;
  std::string name_;
  std::size_t line_;
};

// A row's type code, on every row (later frames' too): Sibernetic's 1.x, 2.x or 3.x only. KindOf
// would read 1.4e6 as boundary, and 1e30 as a boundary particle the header did not count.
inline float ReadTypeCode(TextCursor& in) {
  const float type = in.Number<float>("particle type");
  if (!IsSiberneticTypeCode(type))
    in.Fail("particle type " + FormatNumber(type) + ": " + kExpectedTypeCode);
  return type;
}

struct Header {
  Box box;
  std::size_t elastic = 0, liquid = 0, boundary = 0;
  double time_step_s = 0;
  int log_step = 1;
  std::size_t particles() const { return elastic + liquid + boundary; }
  std::size_t moving() const { return elastic + liquid; }
};

// Each particle of frame 0 takes a row of at least 8 bytes ("0 0 0 1\n"): a header declaring more
// particles than the file can hold is wrong, and must not size any allocation.
constexpr std::size_t kMinRowBytes = 8;

// The 11 header lines; text_bytes bounds the particle counts (see kMinRowBytes).
Header ParseHeader(TextCursor& in, std::size_t text_bytes);

// What the row parser counted, for the layout decision.
struct RowCounts {
  std::size_t rows = 0;  // position rows parsed
  std::size_t boundary_rows_after_first_frame = 0;
  std::size_t first_row_line = 0;
  // Rows read as the OpenCL layout (every later frame completed with frame 0's boundary rows)
  // until a boundary row where frame 2 would start showed a native dump.
  bool expanded = false;
};

// Whether rows start out read as the OpenCL layout, and whether row `rows` (0-based, a boundary
// row or not) switches them to native: the one rule both readers follow.
bool StartsExpanded(const Header& h, TextLayout requested);
bool SwitchesToNative(const RowCounts& r, const Header& h, bool boundary_row, TextLayout requested);

// After every row: the first frame's type counts against the header, then the layout (detected,
// or the requested one checked), as ParseSiberneticText decides it. InputError naming `name`.
TextLayout ResolveLayout(const RowCounts& r, const std::vector<float>& first_frame_type,
                         const Header& h, TextLayout requested, const std::string& name);
// Frame f's time, f x log step x time step (the text has no time column), for `frames` frames;
// InputError naming `name` unless they increase (a time step and log step so large that the
// product overflows to infinity).
std::vector<double> FrameTimes(const Header& h, std::size_t frames, const std::string& name);
// Frames the rows make in `layout`.
std::size_t FrameCount(TextLayout layout, std::size_t rows, const Header& h);
// The OpenCL layout needs the moving particles first.
void CheckMovingFirst(const std::vector<float>& type, const Header& h, const std::string& name);
// "opencl layout: 500 frames, 218 elastic + ..." (TextReadReport::description).
std::string DescribeText(TextLayout layout, std::size_t frames, const Header& h);

}  // namespace owval::internal
