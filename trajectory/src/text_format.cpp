// Sibernetic position_buffer.txt: reading (layout detection from the counts) and writing.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

#include "gzip.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/mapped_file.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/base/progress.hpp"
#include "owval/trajectory/formats.hpp"
#include "text_rows.hpp"

namespace owval {
namespace {

// A cursor over the file text that knows its line number, for error messages.
class TextCursor {
 public:
  TextCursor(std::string_view text, const std::string& name)
      : p_(text.data()), end_(text.data() + text.size()), name_(name) {}

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
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(value)) Fail(std::string(what) + " is not finite (NaN or Inf)");
    }
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
  static bool IsSeparator(char c) { return c == '\t' || c == ' ' || c == '\n' || c == '\r'; }

  const char* p_;
  const char* end_;
  std::string name_;
  std::size_t line_ = 1;
};

struct Header {
  Box box;
  std::size_t elastic = 0, liquid = 0, boundary = 0;
  double time_step_s = 0;
  int log_step = 1;
  std::size_t particles() const { return elastic + liquid + boundary; }
  std::size_t moving() const { return elastic + liquid; }
};

// A whole number from 0 to `max`, refused (not converted) otherwise: 1e30 or 1e12 must not
// become 0 or 1 through a float-to-integer conversion.
std::size_t Count(TextCursor& in, const char* what, double max) {
  const double value = in.Number<double>(what);
  if (value < 0 || value != std::floor(value))
    in.Fail(std::string("expected ") + what + " (a whole number)");
  if (value > max) {
    std::ostringstream bound;
    bound << what << " " << value << " is larger than " << static_cast<unsigned long long>(max);
    in.Fail(bound.str());
  }
  return static_cast<std::size_t>(value);
}

// Each particle of frame 0 takes a row of at least 8 bytes ("0 0 0 1\n"): a header declaring more
// particles than the file can hold is wrong, and must not size any allocation.
constexpr std::size_t kMinRowBytes = 8;

Header ParseHeader(TextCursor& in, std::size_t text_bytes) {
  const double max_particles = static_cast<double>(text_bytes / kMinRowBytes);
  Header h;
  float* box_fields[6] = {&h.box.xmin, &h.box.xmax, &h.box.ymin,
                          &h.box.ymax, &h.box.zmin, &h.box.zmax};
  const char* box_names[6] = {"box xmin", "box xmax", "box ymin",
                              "box ymax", "box zmin", "box zmax"};
  for (int i = 0; i < 6; ++i) {
    if (in.at_end())
      in.Fail("truncated header: expected 11 lines (box, counts, time step, log step)");
    *box_fields[i] = in.Number<float>(box_names[i]);
    in.EndOfLine(box_names[i]);
  }
  std::size_t* counts[3] = {&h.elastic, &h.liquid, &h.boundary};
  const char* count_names[3] = {"elastic particle count", "liquid particle count",
                                "boundary particle count"};
  for (int i = 0; i < 3; ++i) {
    if (in.at_end())
      in.Fail("truncated header: expected 11 lines (box, counts, time step, log step)");
    *counts[i] = Count(in, count_names[i], max_particles);
    in.EndOfLine(count_names[i]);
  }
  if (in.at_end()) in.Fail("truncated header: expected the time step on line 10");
  h.time_step_s = in.Number<double>("time step (s)");
  in.EndOfLine("time step");
  if (in.at_end()) in.Fail("truncated header: expected the log step on line 11");
  h.log_step = static_cast<int>(Count(in, "log step", std::numeric_limits<int>::max()));
  in.EndOfLine("log step");
  if (h.particles() == 0) in.Fail("header declares no particles");
  if (h.particles() > text_bytes / kMinRowBytes)
    in.Fail("header declares " + std::to_string(h.particles()) +
            " particles, more rows than the file can hold");
  if (h.time_step_s <= 0) in.Fail("time step must be positive");
  if (h.log_step <= 0) h.log_step = 1;
  return h;
}

struct Rows {
  std::string name;  // the file, for messages
  // Positions as they will be stored. In the OpenCL layout later frames list only the moving
  // particles; while `expanded`, each such frame is completed in place with frame 0's boundary
  // rows (boundary particles never move), so no second copy of the data is ever made.
  std::vector<float> xyz;
  bool expanded = false;
  std::vector<float> first_frame_type;  // types of the first `particles` rows
  std::size_t rows = 0;
  std::size_t boundary_rows_after_first_frame = 0;
  std::size_t first_row_line = 0;
};

// Reserves room for the positions a text of `bytes` can hold, backed by huge pages.
void ReserveForText(Rows& r, const Header& h, std::size_t bytes) {
  const std::size_t rows = bytes / 24 + h.particles();  // Sibernetic's rows take 24 to 32 bytes
  const std::size_t floats =
      r.expanded ? SaturatingProduct(1 + rows / h.moving(), h.particles() * 3) : rows * 3;
  // An estimate, capped at 8 floats per byte of text (demo1's buffer expands to 6: 343 moving
  // rows a frame, 17,841 particles): a header whose counts would expand a small file further
  // grows the vector instead, and that growth is checked against the memory budget frame by frame.
  r.xyz.reserve(std::min({floats, SaturatingProduct(bytes, 8) + 3 * h.particles(),
                          MemoryBudgetBytes() / sizeof(float)}));
  AdviseHugePages(r.xyz.data(), r.xyz.capacity() * sizeof(float));
}

void AppendBoundaryBlock(Rows& r, const Header& h) {
  const std::size_t begin = h.moving() * 3, end = h.particles() * 3;
  if (r.xyz.size() + end - begin > r.xyz.capacity())  // the vector is about to grow
    CheckAllocation((r.xyz.size() + end - begin) * sizeof(float) * 2, r.name,
                    "the positions (the opencl layout repeats the boundary rows in every frame)");
  r.xyz.insert(r.xyz.end(), r.xyz.begin() + static_cast<std::ptrdiff_t>(begin),
               r.xyz.begin() + static_cast<std::ptrdiff_t>(end));
}

// Before storing row r of an expanded OpenCL buffer: completes the previous frame when r starts
// a new one. A boundary row where frame 2 would start means the file is a native dump (frame 1
// carries its boundary rows): the rows stored so far are then exactly a native prefix.
void BeforeRow(Rows& r, const Header& h, bool boundary_row, bool may_switch) {
  const std::size_t n = h.particles(), m = h.moving();
  if (r.rows <= n || (r.rows - n) % m != 0) return;
  if (boundary_row && r.rows == n + m && may_switch) {
    r.expanded = false;
    return;
  }
  AppendBoundaryBlock(r, h);
}

Rows ParseRows(TextCursor& in, const Header& h, std::string_view text, TextLayout requested,
               bool quiet) {
  Rows r;
  r.name = in.name();
  r.first_row_line = in.line();
  r.expanded = requested != TextLayout::kNative && h.moving() > 0 && h.boundary > 0;
  const bool may_switch = requested == TextLayout::kAuto;
  ReserveForText(r, h, text.size() - in.offset(text));
  r.first_frame_type.reserve(h.particles());
  Progress progress("parse", text.size(), quiet || text.size() < (64u << 20));
  while (true) {
    in.SkipEmptyTail();
    if (in.at_end()) break;
    const float x = in.Number<float>("x"), y = in.Number<float>("y"), z = in.Number<float>("z");
    const float type = in.Number<float>("particle type");
    in.EndOfLine("particle type");
    const bool boundary_row = type >= 3.0f && type < 4.0f;  // no cast: 1e30 is finite
    if (r.rows < h.particles()) {
      r.first_frame_type.push_back(type);
    } else if (boundary_row) {
      ++r.boundary_rows_after_first_frame;
    }
    if (r.expanded) BeforeRow(r, h, boundary_row, may_switch);
    r.xyz.push_back(x);
    r.xyz.push_back(y);
    r.xyz.push_back(z);
    ++r.rows;
    if ((r.rows & 0xFFFFF) == 0) progress.Update(in.offset(text));
  }
  const std::size_t n = h.particles();
  if (r.expanded && r.rows > n && (r.rows - n) % h.moving() == 0) AppendBoundaryBlock(r, h);
  return r;
}

void CheckFirstFrameTypes(const Rows& r, const Header& h, const std::string& name) {
  std::size_t elastic = 0, liquid = 0, boundary = 0;
  for (float t : r.first_frame_type) {
    switch (KindOf(t)) {
      case ParticleKind::kElastic:
        ++elastic;
        break;
      case ParticleKind::kLiquid:
        ++liquid;
        break;
      case ParticleKind::kBoundary:
        ++boundary;
        break;
    }
  }
  if (elastic != h.elastic || liquid != h.liquid || boundary != h.boundary) {
    std::ostringstream msg;
    msg << "wrong particle counts: header says " << h.elastic << " elastic, " << h.liquid
        << " liquid, " << h.boundary << " boundary; the first frame has " << elastic << ", "
        << liquid << ", " << boundary;
    throw InputError(name, r.first_row_line, msg.str());
  }
}

bool FitsOpenCL(std::size_t rows, const Header& h) {
  if (rows < h.particles()) return false;
  if (h.moving() == 0) return rows == h.particles();
  return (rows - h.particles()) % h.moving() == 0;
}
bool FitsNative(std::size_t rows, const Header& h) { return rows > 0 && rows % h.particles() == 0; }

TextLayout DetectLayout(const Rows& r, const Header& h, const std::string& name) {
  const bool opencl = FitsOpenCL(r.rows, h);
  const bool native = FitsNative(r.rows, h);
  if (opencl && !native) return TextLayout::kOpenCL;
  if (native && !opencl) return TextLayout::kNative;
  if (opencl && native) {
    // Both fit by counts: the type column decides. Later frames of an OpenCL buffer hold no
    // boundary rows; a native dump holds all of them in every frame.
    if (h.boundary == 0 || r.rows == h.particles()) return TextLayout::kOpenCL;  // layouts coincide
    if (r.boundary_rows_after_first_frame == 0) return TextLayout::kOpenCL;
    if (r.boundary_rows_after_first_frame == (r.rows / h.particles() - 1) * h.boundary)
      return TextLayout::kNative;
  }
  std::ostringstream msg;
  msg << r.rows << " position rows fit neither layout for header counts " << h.elastic
      << " elastic + " << h.liquid << " liquid + " << h.boundary << " boundary: opencl needs "
      << h.particles() << " + k*" << h.moving() << " rows, native needs k*" << h.particles()
      << " (truncated file or wrong counts?); pass --layout opencl|native to override detection";
  throw InputError(name, 0, msg.str());
}

void CheckForcedLayout(TextLayout layout, const Rows& r, const Header& h, const std::string& name) {
  const bool fits = layout == TextLayout::kOpenCL ? FitsOpenCL(r.rows, h) : FitsNative(r.rows, h);
  if (fits) return;
  std::ostringstream msg;
  msg << r.rows << " position rows do not fit the requested " << LayoutName(layout)
      << " layout for " << h.particles() << " particles (" << h.moving()
      << " moving): the last frame is incomplete";
  throw InputError(name, 0, msg.str());
}

Trajectory Assemble(Rows&& r, const Header& h, TextLayout layout) {
  Trajectory t;
  t.box = h.box;
  t.time_step_s = h.time_step_s;
  t.log_step = h.log_step;
  t.type = std::move(r.first_frame_type);
  const std::size_t n = h.particles();
  const std::size_t frames = layout == TextLayout::kNative ? r.rows / n
                             : h.moving() == 0             ? 1
                                                           : 1 + (r.rows - n) / h.moving();
  t.positions = std::move(r.xyz);
  t.time_s.resize(frames);
  for (std::size_t f = 0; f < frames; ++f)
    t.time_s[f] = static_cast<double>(f) * h.log_step * h.time_step_s;
  return t;
}

std::string Describe(TextLayout layout, const Trajectory& t, const Header& h) {
  std::ostringstream s;
  s << LayoutName(layout) << " layout: " << t.frame_count() << " frames, " << h.elastic
    << " elastic + " << h.liquid << " liquid + " << h.boundary << " boundary particles, dt "
    << h.time_step_s << " s, log step " << h.log_step;
  return s.str();
}

void CheckMovingFirst(const Trajectory& t, const Header& h, const std::string& name) {
  // The OpenCL layout lists only the first E+L particles in later frames; that is only
  // meaningful when the boundary particles come last.
  for (std::size_t i = 0; i < h.moving(); ++i) {
    if (KindOf(t.type[i]) == ParticleKind::kBoundary)
      throw InputError(name, 0,
                       "boundary particle at row " + std::to_string(i) +
                           " of frame 0: expected elastic and liquid particles first");
  }
}

}  // namespace

const char* LayoutName(TextLayout layout) {
  switch (layout) {
    case TextLayout::kAuto:
      return "auto";
    case TextLayout::kOpenCL:
      return "opencl";
    case TextLayout::kNative:
      return "native";
  }
  return "?";
}

TextLayout ParseLayout(const std::string& name) {
  if (name == "auto") return TextLayout::kAuto;
  if (name == "opencl") return TextLayout::kOpenCL;
  if (name == "native") return TextLayout::kNative;
  throw InputError("unknown layout '" + name + "': expected auto, opencl or native");
}

Trajectory ParseSiberneticText(std::string_view text, const std::string& name,
                               const TextReadOptions& options, TextReadReport* report) {
  if (text.empty())
    throw InputError(name, 0, "empty file: expected an 11-line header and particle rows");
  // Every row ends with a newline; a file cut mid-row can still look like whole numbers
  // ("2.1" cut to "2"), so a missing final newline is how truncation shows.
  if (text.back() != '\n') {
    const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    throw InputError(name, lines, "truncated file: the last line does not end with a newline");
  }
  TextCursor in(text, name);
  const Header header = ParseHeader(in, text.size());
  Rows rows = ParseRows(in, header, text, options.layout, options.quiet);
  if (rows.rows < header.particles()) {
    throw InputError(name, in.line(),
                     "truncated first frame: expected " + std::to_string(header.particles()) +
                         " rows, found " + std::to_string(rows.rows));
  }
  CheckFirstFrameTypes(rows, header, name);
  TextLayout layout = options.layout;
  if (layout == TextLayout::kAuto) {
    layout = DetectLayout(rows, header, name);
  } else {
    CheckForcedLayout(layout, rows, header, name);
  }
  // Rows were stored as the OpenCL layout needs them until a native frame showed up; the two
  // agree when there are no boundary (or no moving) particles.
  const bool stored_as_opencl = rows.expanded || header.boundary == 0 || header.moving() == 0;
  if ((layout == TextLayout::kOpenCL) != stored_as_opencl && rows.rows > header.particles()) {
    throw InputError(name, 0,
                     std::string("rows look like the ") + (stored_as_opencl ? "opencl" : "native") +
                         " layout but their counts fit the " + LayoutName(layout) +
                         " layout; pass --layout opencl|native to say which it is");
  }
  const std::size_t row_count = rows.rows;
  Trajectory t = Assemble(std::move(rows), header, layout);
  if (layout == TextLayout::kOpenCL) CheckMovingFirst(t, header, name);
  t.provenance["source_file"] = name;
  t.provenance["source_layout"] = LayoutName(layout);
  if (report) {
    report->detected = layout;
    report->rows = row_count;
    report->bytes = text.size();
    report->description = Describe(layout, t, header);
  }
  return t;
}

Trajectory ReadSiberneticText(const std::filesystem::path& path, const TextReadOptions& options,
                              TextReadReport* report) {
  const MappedFile file(path);
  if (internal::IsGzip(file.text()))
    return ParseSiberneticText(internal::Gunzip(file.text(), path.string()), path.string(), options,
                               report);
  return ParseSiberneticText(file.text(), path.string(), options, report);
}

namespace internal {

void AppendNumber(std::string& out, float value) {
  char buffer[32];
  auto [end, ec] =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 6);
  out.append(buffer, end);
}

void AppendRow(std::string& out, const float* xyz, float type) {
  AppendNumber(out, xyz[0]);
  out.push_back('\t');
  AppendNumber(out, xyz[1]);
  out.push_back('\t');
  AppendNumber(out, xyz[2]);
  out.push_back('\t');
  AppendNumber(out, type);
  out.push_back('\n');
}

std::string TextHeader(const Box& box, const std::vector<float>& type, double time_step_s,
                       int log_step) {
  std::string out;
  for (float v : {box.xmin, box.xmax, box.ymin, box.ymax, box.zmin, box.zmax}) {
    AppendNumber(out, v);
    out.push_back('\n');
  }
  for (ParticleKind kind :
       {ParticleKind::kElastic, ParticleKind::kLiquid, ParticleKind::kBoundary}) {
    out += std::to_string(
        std::count_if(type.begin(), type.end(), [kind](float t) { return KindOf(t) == kind; }));
    out.push_back('\n');
  }
  char dt[32];
  auto [end, ec] = std::to_chars(dt, dt + sizeof dt, time_step_s, std::chars_format::general, 6);
  out.append(dt, end);
  out.push_back('\n');
  out += std::to_string(log_step);
  out.push_back('\n');
  return out;
}

}  // namespace internal

void WriteSiberneticText(const Trajectory& t, const std::filesystem::path& path,
                         TextLayout layout) {
  t.CheckShape();
  const std::size_t n = t.particle_count();
  std::size_t moving = n - t.count(ParticleKind::kBoundary);
  if (layout == TextLayout::kOpenCL) {
    for (std::size_t i = 0; i < moving; ++i)
      if (KindOf(t.type[i]) == ParticleKind::kBoundary)
        throw InputError(path.string(), 0,
                         "cannot write the opencl layout: boundary particles must come last");
  }
  AtomicOutput out(path);
  std::string buffer = internal::TextHeader(t.box, t.type, t.time_step_s, t.log_step);
  buffer.reserve(1 << 22);
  for (std::size_t f = 0; f < t.frame_count(); ++f) {
    const std::size_t rows = (f == 0 || layout == TextLayout::kNative) ? n : moving;
    for (std::size_t i = 0; i < rows; ++i) internal::AppendRow(buffer, t.position(f, i), t.type[i]);
    if (buffer.size() > (1 << 22)) {
      out.stream().write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.stream().write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  out.Commit();
}

}  // namespace owval
