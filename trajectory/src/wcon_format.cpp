// WCON writer and the whole-track read (tracker-commons WCON_format.md). See worm_formats.hpp;
// the reader itself is wcon_reader.cpp.
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/trajectory/worm_formats.hpp"
#include "wcon_units.hpp"

namespace owval {
namespace {
using nlohmann::json;

void Check(const WormTrack& t, const std::string& name) {
  const std::size_t n = t.time_s.size();
  auto fail = [&](const std::string& what) { throw InputError(name, 0, what); };
  if (n == 0) fail("WCON needs at least one time point");
  if (t.x_mm.size() != n || t.y_mm.size() != n) fail("x and y need one array per time point");
  if (!t.cx_mm.empty() && (t.cx_mm.size() != n || t.cy_mm.size() != n))
    fail("cx and cy need one value per time point");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(t.time_s[i]) || (i > 0 && !(t.time_s[i] > t.time_s[i - 1])))
      fail("t must be finite and increasing (time point " + std::to_string(i) + ")");
    if (t.x_mm[i].size() != t.y_mm[i].size() || t.x_mm[i].empty())
      fail("x and y of time point " + std::to_string(i) + " must be non-empty and equal in length");
    for (std::size_t k = 0; k < t.x_mm[i].size(); ++k)
      if (!std::isfinite(t.x_mm[i][k]) || !std::isfinite(t.y_mm[i][k]))
        fail("non-finite x/y at time point " + std::to_string(i));
  }
}

// Floats with 9 significant digits, doubles with 17: both read back to the same value.
template <typename T>
void AppendNumber(std::string* s, T value, bool first) {
  char buffer[40];
  const char* format = sizeof(T) == sizeof(float) ? "%s%.9g" : "%s%.17g";
  std::snprintf(buffer, sizeof buffer, format, first ? "" : ",", static_cast<double>(value));
  *s += buffer;
}

template <typename T>
void AppendArray(std::string* s, const std::vector<T>& v) {
  *s += '[';
  for (std::size_t i = 0; i < v.size(); ++i) AppendNumber(s, v[i], i == 0);
  *s += ']';
}

// Time point i's array in the "x" or "y" block.
void AppendNestedElement(std::string* s, const std::vector<float>& v, std::size_t i) {
  *s += i ? ",\n    " : "\n    ";
  AppendArray(s, v);
}

// The text before the data's arrays: units, metadata, "@owval", the record's id and head, "t": .
std::string HeadText(const WormTrack& t) {
  json head = {{"units", {{"t", "s"}, {"x", "mm"}, {"y", "mm"}, {"cx", "mm"}, {"cy", "mm"}}},
               {"metadata",
                {{"software",
                  {{"name", "owval"},
                   {"version", t.software_version},
                   {"featureID", "@owval"},
                   {"settings", t.software_settings}}}}},
               {"@owval", t.owval}};
  std::string s = head.dump(1);
  s.pop_back();  // the closing brace: the data block follows
  while (!s.empty() && s.back() == '\n') s.pop_back();
  s += ",\n \"data\": [\n  {\"id\": " + json(t.id).dump() + ", \"head\": \"L\",\n   \"t\": ";
  return s;
}

// What separates the arrays (t, cx, cy, x, y), and what ends the file.
constexpr const char* kArrayOpen[5] = {"[", ",\n   \"cx\": [", ",\n   \"cy\": [", ",\n   \"x\": [",
                                       ",\n   \"y\": ["};
constexpr const char* kTail = "}\n ]\n}\n";

}  // namespace

std::string WconText(const WormTrack& t) {
  std::string s = HeadText(t);
  AppendArray(&s, t.time_s);
  if (!t.cx_mm.empty()) {
    s += ",\n   \"cx\": ";
    AppendArray(&s, t.cx_mm);
    s += ",\n   \"cy\": ";
    AppendArray(&s, t.cy_mm);
  }
  s += kArrayOpen[3];
  for (std::size_t i = 0; i < t.x_mm.size(); ++i) AppendNestedElement(&s, t.x_mm[i], i);
  s += "]";
  s += kArrayOpen[4];
  for (std::size_t i = 0; i < t.y_mm.size(); ++i) AppendNestedElement(&s, t.y_mm[i], i);
  s += "]";
  s += kTail;
  return s;
}

void WriteWcon(const WormTrack& track, const std::filesystem::path& path) {
  Check(track, path.string());
  WriteFileAtomically(path, WconText(track));
}

WconWriter::WconWriter(std::filesystem::path path, const WormTrack& head, bool centroid)
    : path_(std::move(path)), head_(HeadText(head)), centroid_(centroid) {}

WconWriter::~WconWriter() {
  for (std::FILE* f : spools_)
    if (f) std::fclose(f);
}

std::FILE* WconWriter::Spool(int array) {
  if (!spools_[array]) spools_[array] = std::tmpfile();
  if (!spools_[array]) throw InputError(path_.string(), 0, "cannot create a temporary file");
  return spools_[array];
}

void WconWriter::Append(double time_s, const std::vector<float>& x_mm,
                        const std::vector<float>& y_mm, double cx_mm, double cy_mm) {
  const std::size_t i = points_;
  auto fail = [&](const std::string& what) { throw InputError(path_.string(), 0, what); };
  if (!std::isfinite(time_s) || (i > 0 && !(time_s > last_time_s_)))
    fail("t must be finite and increasing (time point " + std::to_string(i) + ")");
  if (x_mm.size() != y_mm.size() || x_mm.empty())
    fail("x and y of time point " + std::to_string(i) + " must be non-empty and equal in length");
  for (std::size_t k = 0; k < x_mm.size(); ++k)
    if (!std::isfinite(x_mm[k]) || !std::isfinite(y_mm[k]))
      fail("non-finite x/y at time point " + std::to_string(i));
  std::string text[5];
  AppendNumber(&text[0], time_s, i == 0);
  if (centroid_) {
    AppendNumber(&text[1], cx_mm, i == 0);
    AppendNumber(&text[2], cy_mm, i == 0);
  }
  AppendNestedElement(&text[3], x_mm, i);
  AppendNestedElement(&text[4], y_mm, i);
  for (int a = 0; a < 5; ++a)
    if (!text[a].empty() &&
        std::fwrite(text[a].data(), 1, text[a].size(), Spool(a)) != text[a].size())
      fail("cannot write a temporary file");
  last_time_s_ = time_s;
  ++points_;
}

void WconWriter::Commit() {
  if (points_ == 0) throw InputError(path_.string(), 0, "WCON needs at least one time point");
  AtomicOutput out(path_);
  std::ofstream& stream = out.stream();
  stream << head_;
  char buffer[1 << 16];
  for (int a = 0; a < 5; ++a) {
    if (!centroid_ && (a == 1 || a == 2)) continue;
    stream << kArrayOpen[a];
    std::FILE* spool = Spool(a);
    std::rewind(spool);
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, spool)) > 0;)
      stream.write(buffer, static_cast<std::streamsize>(n));
    if (std::ferror(spool)) throw InputError(path_.string(), 0, "cannot read a temporary file");
    stream << "]";
  }
  stream << kTail;
  out.Commit();
}

// Factor to SI-based owval units (s for time, mm for lengths); 0 when unknown.
double WconTimeFactor(const std::string& u) {
  static const std::map<std::string, double> f = {{"s", 1},
                                                  {"sec", 1},
                                                  {"second", 1},
                                                  {"seconds", 1},
                                                  {"ms", 1e-3},
                                                  {"millisecond", 1e-3},
                                                  {"milliseconds", 1e-3},
                                                  {"min", 60},
                                                  {"minute", 60},
                                                  {"minutes", 60},
                                                  {"h", 3600},
                                                  {"hour", 3600},
                                                  {"hours", 3600}};
  const auto it = f.find(u);
  return it == f.end() ? 0 : it->second;
}

double WconLengthFactor(const std::string& u) {
  static const std::map<std::string, double> f = {{"mm", 1},
                                                  {"millimetre", 1},
                                                  {"millimeter", 1},
                                                  {"millimetres", 1},
                                                  {"millimeters", 1},
                                                  {"um", 1e-3},
                                                  {"\u00b5m", 1e-3},
                                                  {"\u03bcm", 1e-3},
                                                  {"micrometre", 1e-3},
                                                  {"micrometer", 1e-3},
                                                  {"micrometres", 1e-3},
                                                  {"micrometers", 1e-3},
                                                  {"m", 1e3},
                                                  {"metre", 1e3},
                                                  {"meter", 1e3},
                                                  {"metres", 1e3},
                                                  {"meters", 1e3},
                                                  {"cm", 10},
                                                  {"centimetre", 10},
                                                  {"centimeter", 10}};
  const auto it = f.find(u);
  return it == f.end() ? 0 : it->second;
}

void AppendTimePoint(const WconTimePoint& point, bool centroid, WormTrack* track) {
  track->time_s.push_back(point.time_s);
  track->x_mm.push_back(point.x_mm);
  track->y_mm.push_back(point.y_mm);
  if (!centroid) return;
  track->cx_mm.push_back(point.cx_mm);
  track->cy_mm.push_back(point.cy_mm);
}

WormTrack ReadWcon(const std::filesystem::path& path) {
  WconReader reader(path);
  WormTrack track = reader.head();
  WconTimePoint point;
  while (reader.Next(&point)) AppendTimePoint(point, reader.has_centroid(), &track);
  return track;
}

}  // namespace owval
