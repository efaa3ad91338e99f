// WCON writer and reader (tracker-commons WCON_format.md). See worm_formats.hpp.
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/json_file.hpp"
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

namespace {

struct WconReader {
  std::string name;
  double t_factor = 1, x_factor = 1, y_factor = 1, cx_factor = 1, cy_factor = 1;

  [[noreturn]] void Fail(const std::string& what) const { throw InputError(name, 0, what); }

  double Unit(const json& units, const char* key, bool length) const {
    if (!units.contains(key) || !units[key].is_string())
      Fail(std::string("units.") + key + ": expected a unit string");
    const std::string u = units[key].get<std::string>();
    const double f = length ? WconLengthFactor(u) : WconTimeFactor(u);
    if (f == 0) Fail(std::string("units.") + key + ": unsupported unit \"" + u + "\"");
    return f;
  }

  std::vector<double> Numbers(const json& v, const std::string& field) const {
    if (!v.is_array()) Fail(field + ": expected an array of numbers");
    std::vector<double> out;
    for (const json& e : v) {
      if (!e.is_number()) Fail(field + ": expected numbers (null and non-numbers unsupported)");
      out.push_back(e.get<double>());
    }
    return out;
  }

  template <typename Stored>
  Stored Millimetres(double value_mm, const std::string& field) const {
    return WconMillimetres<Stored>(value_mm, name, field);
  }

  // One record's time points appended to the track.
  void Record(const json& r, std::size_t index, WormTrack* t) const {
    const std::string at = "data[" + std::to_string(index) + "].";
    const std::vector<double> time = Numbers(r.at("t"), at + "t");
    if (time.empty()) Fail(at + "t: must not be empty");
    const json &x = r.at("x"), &y = r.at("y");
    if (!x.is_array() || !y.is_array() || x.size() != time.size() || y.size() != time.size())
      Fail(at + "x/y: expected one array per time point");
    std::vector<double> ox(time.size(), 0), oy(time.size(), 0);
    if (r.contains("ox")) ox = Numbers(r["ox"], at + "ox");
    if (r.contains("oy")) oy = Numbers(r["oy"], at + "oy");
    if (ox.size() != time.size() || oy.size() != time.size()) Fail(at + "ox/oy: one per time");
    for (std::size_t i = 0; i < time.size(); ++i) {
      const std::string w = at + "x/y[" + std::to_string(i) + "]";
      const std::vector<double> xi =
          x[i].is_array() ? Numbers(x[i], w) : Numbers(json::array({x[i]}), w);
      const std::vector<double> yi =
          y[i].is_array() ? Numbers(y[i], w) : Numbers(json::array({y[i]}), w);
      if (xi.size() != yi.size() || xi.empty()) Fail(w + ": x and y must be equal in length");
      std::vector<float> fx, fy;
      for (std::size_t k = 0; k < xi.size(); ++k) {
        fx.push_back(Millimetres<float>((xi[k] + ox[i]) * x_factor, w));
        fy.push_back(Millimetres<float>((yi[k] + oy[i]) * y_factor, w));
      }
      t->time_s.push_back(time[i] * t_factor);
      t->x_mm.push_back(std::move(fx));
      t->y_mm.push_back(std::move(fy));
    }
    if (r.contains("cx") != r.contains("cy")) Fail(at + "cx/cy: must come in pairs");
    if (r.contains("cx")) {
      const std::vector<double> cx = Numbers(r["cx"], at + "cx"), cy = Numbers(r["cy"], at + "cy");
      if (cx.size() != time.size() || cy.size() != time.size()) Fail(at + "cx/cy: one per time");
      for (std::size_t i = 0; i < time.size(); ++i) {
        const std::string w = at + "cx/cy[" + std::to_string(i) + "]";
        t->cx_mm.push_back(Millimetres<double>((cx[i] + ox[i]) * cx_factor, w));
        t->cy_mm.push_back(Millimetres<double>((cy[i] + oy[i]) * cy_factor, w));
      }
    }
  }
};

}  // namespace

WormTrack ReadWcon(const std::filesystem::path& path) {
  WconReader reader{path.string()};
  // InputError naming the file and line, for a number too large for a double (1e400) too
  const json doc = ParseJsonText(ReadWholeFile(path), path.string());
  if (!doc.is_object() || !doc.contains("units") || !doc.contains("data"))
    reader.Fail("expected a WCON object with \"units\" and \"data\"");
  const json& units = doc["units"];
  if (!units.is_object()) reader.Fail("units: expected an object");
  reader.t_factor = reader.Unit(units, "t", false);
  reader.x_factor = reader.Unit(units, "x", true);
  reader.y_factor = reader.Unit(units, "y", true);
  const json records = doc["data"].is_array() ? doc["data"] : json::array({doc["data"]});
  WormTrack t;
  bool first = true;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const json& r = records[i];
    const std::string at = "data[" + std::to_string(i) + "]";
    if (!r.is_object() || !r.contains("id") || !r.contains("t") || !r.contains("x") ||
        !r.contains("y"))
      reader.Fail(at + ": expected a record with id, t, x and y");
    if (!r["id"].is_string()) reader.Fail(at + ".id: expected a string");
    if (first) {
      t.id = r["id"].get<std::string>();
      if (r.contains("cx")) {
        reader.cx_factor = reader.Unit(units, "cx", true);
        reader.cy_factor = reader.Unit(units, "cy", true);
      }
      first = false;
    }
    if (r["id"].get<std::string>() == t.id) reader.Record(r, i, &t);
  }
  if (t.time_s.empty()) reader.Fail("data: no time point");
  if (doc.contains("metadata") && doc["metadata"].is_object() &&
      doc["metadata"].contains("software") && doc["metadata"]["software"].is_object()) {
    const json& sw = doc["metadata"]["software"];
    if (sw.contains("version") && sw["version"].is_string()) t.software_version = sw["version"];
    if (sw.contains("settings")) t.software_settings = sw["settings"];
  }
  if (doc.contains("@owval")) t.owval = doc["@owval"];
  // Finite too: a t of 1e308 in hours is infinite in seconds.
  CheckFrameTimesIncrease(t.time_s, path.string(), "data: t: ");
  return t;
}

}  // namespace owval
