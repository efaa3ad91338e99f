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
#include "text_cursor.hpp"
#include "text_rows.hpp"

namespace owval {
namespace internal {
namespace {

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

}  // namespace

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
    // An inverted box (the engine's configuration reader refuses one too) would frame the camera
    // and the stability gate's "outside the box" on nothing.
    if (i % 2 == 1 && *box_fields[i] < *box_fields[i - 1])
      in.Fail(std::string(box_names[i]) + " " + FormatNumber(*box_fields[i]) + " is below " +
              box_names[i - 1] + " " + FormatNumber(*box_fields[i - 1]));
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
  if (h.time_step_s <= 0) in.Fail("time step must be positive");  // on its own line
  in.EndOfLine("time step");
  if (in.at_end()) in.Fail("truncated header: expected the log step on line 11");
  h.log_step = static_cast<int>(Count(in, "log step", std::numeric_limits<int>::max()));
  // Sibernetic writes frame k when k % logstep == 0: 0 is no log step (a 1 in its place made the
  // times and speeds of a log-step-10 file ten times off).
  if (h.log_step <= 0) in.Fail("log step must be a positive whole number");
  in.EndOfLine("log step");
  if (h.particles() == 0) in.Fail("header declares no particles");
  if (h.particles() > text_bytes / kMinRowBytes)
    in.Fail("header declares " + std::to_string(h.particles()) +
            " particles, more rows than the file can hold");
  return h;
}

}  // namespace internal

namespace {

using internal::Header;
using internal::TextCursor;

struct Rows : internal::RowCounts {
  std::string name;  // the file, for messages
  // Positions as they will be stored. In the OpenCL layout later frames list only the moving
  // particles; while `expanded`, each such frame is completed in place with frame 0's boundary
  // rows (boundary particles never move), so no second copy of the data is ever made.
  std::vector<float> xyz;
  std::vector<float> first_frame_type;  // types of the first `particles` rows
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
void BeforeRow(Rows& r, const Header& h, bool boundary_row, TextLayout requested) {
  const std::size_t n = h.particles(), m = h.moving();
  if (r.rows <= n || (r.rows - n) % m != 0) return;
  if (internal::SwitchesToNative(r, h, boundary_row, requested)) {
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
  r.expanded = internal::StartsExpanded(h, requested);
  ReserveForText(r, h, text.size() - in.offset(text));
  r.first_frame_type.reserve(h.particles());
  Progress progress("parse", text.size(), quiet || text.size() < (64u << 20));
  while (true) {
    in.SkipEmptyTail();
    if (in.at_end()) break;
    const float x = in.Coordinate("x"), y = in.Coordinate("y"), z = in.Coordinate("z");
    const float type = internal::ReadTypeCode(in);
    in.EndOfLine("particle type");
    const bool boundary_row = type >= 3.0f && type < 4.0f;  // no cast: 1e30 is finite
    if (r.rows < h.particles()) {
      r.first_frame_type.push_back(type);
    } else if (boundary_row) {
      ++r.boundary_rows_after_first_frame;
    }
    if (r.expanded) BeforeRow(r, h, boundary_row, requested);
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

}  // namespace

namespace internal {
namespace {

void CheckFirstFrameTypes(const RowCounts& r, const std::vector<float>& first_frame_type,
                          const Header& h, const std::string& name) {
  std::size_t elastic = 0, liquid = 0, boundary = 0;
  for (float t : first_frame_type) {
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

TextLayout DetectLayout(const RowCounts& r, const Header& h, const std::string& name) {
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

void CheckForcedLayout(TextLayout layout, const RowCounts& r, const Header& h,
                       const std::string& name) {
  const bool fits = layout == TextLayout::kOpenCL ? FitsOpenCL(r.rows, h) : FitsNative(r.rows, h);
  if (fits) return;
  std::ostringstream msg;
  msg << r.rows << " position rows do not fit the requested " << LayoutName(layout)
      << " layout for " << h.particles() << " particles (" << h.moving()
      << " moving): the last frame is incomplete";
  throw InputError(name, 0, msg.str());
}

}  // namespace

bool StartsExpanded(const Header& h, TextLayout requested) {
  return requested != TextLayout::kNative && h.moving() > 0 && h.boundary > 0;
}

bool SwitchesToNative(const RowCounts& r, const Header& h, bool boundary_row,
                      TextLayout requested) {
  return boundary_row && r.rows == h.particles() + h.moving() && requested == TextLayout::kAuto;
}

TextLayout ResolveLayout(const RowCounts& r, const std::vector<float>& first_frame_type,
                         const Header& h, TextLayout requested, const std::string& name) {
  CheckFirstFrameTypes(r, first_frame_type, h, name);
  TextLayout layout = requested;
  if (layout == TextLayout::kAuto) {
    layout = DetectLayout(r, h, name);
  } else {
    CheckForcedLayout(layout, r, h, name);
  }
  // Rows were stored as the OpenCL layout needs them until a native frame showed up; the two
  // agree when there are no boundary (or no moving) particles.
  const bool stored_as_opencl = r.expanded || h.boundary == 0 || h.moving() == 0;
  if ((layout == TextLayout::kOpenCL) != stored_as_opencl && r.rows > h.particles()) {
    throw InputError(name, 0,
                     std::string("rows look like the ") + (stored_as_opencl ? "opencl" : "native") +
                         " layout but their counts fit the " + LayoutName(layout) +
                         " layout; pass --layout opencl|native to say which it is");
  }
  return layout;
}

std::vector<double> FrameTimes(const Header& h, std::size_t frames, const std::string& name) {
  std::vector<double> time_s(frames);
  for (std::size_t f = 0; f < frames; ++f)
    time_s[f] = static_cast<double>(f) * h.log_step * h.time_step_s;
  CheckFrameTimesIncrease(time_s, name, "frame time = frame x log step x time step (header): ");
  return time_s;
}

std::size_t FrameCount(TextLayout layout, std::size_t rows, const Header& h) {
  const std::size_t n = h.particles();
  return layout == TextLayout::kNative ? rows / n
         : h.moving() == 0             ? 1
                                       : 1 + (rows - n) / h.moving();
}

std::string DescribeText(TextLayout layout, std::size_t frames, const Header& h) {
  std::ostringstream s;
  s << LayoutName(layout) << " layout: " << frames << " frames, " << h.elastic << " elastic + "
    << h.liquid << " liquid + " << h.boundary << " boundary particles, dt " << h.time_step_s
    << " s, log step " << h.log_step;
  return s.str();
}

void CheckMovingFirst(const std::vector<float>& type, const Header& h, const std::string& name) {
  // The OpenCL layout lists only the first E+L particles in later frames; that is only
  // meaningful when the boundary particles come last.
  for (std::size_t i = 0; i < h.moving(); ++i) {
    if (KindOf(type[i]) == ParticleKind::kBoundary)
      throw InputError(name, 0,
                       "boundary particle at row " + std::to_string(i) +
                           " of frame 0: expected elastic and liquid particles first");
  }
}

}  // namespace internal

namespace {

Trajectory Assemble(Rows&& r, const Header& h, TextLayout layout) {
  Trajectory t;
  t.box = h.box;
  t.time_step_s = h.time_step_s;
  t.log_step = h.log_step;
  t.type = std::move(r.first_frame_type);
  const std::size_t frames = internal::FrameCount(layout, r.rows, h);
  t.positions = std::move(r.xyz);
  t.time_s = internal::FrameTimes(h, frames, r.name);
  return t;
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
  const Header header = internal::ParseHeader(in, text.size());
  Rows rows = ParseRows(in, header, text, options.layout, options.quiet);
  if (rows.rows < header.particles()) {
    throw InputError(name, in.line(),
                     "truncated first frame: expected " + std::to_string(header.particles()) +
                         " rows, found " + std::to_string(rows.rows));
  }
  const TextLayout layout =
      internal::ResolveLayout(rows, rows.first_frame_type, header, options.layout, name);
  const std::size_t row_count = rows.rows;
  Trajectory t = Assemble(std::move(rows), header, layout);
  if (layout == TextLayout::kOpenCL) internal::CheckMovingFirst(t.type, header, name);
  t.provenance["source_file"] = name;
  t.provenance["source_layout"] = LayoutName(layout);
  if (report) {
    report->detected = layout;
    report->rows = row_count;
    report->bytes = text.size();
    report->description = internal::DescribeText(layout, t.frame_count(), header);
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
