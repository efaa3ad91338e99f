// WconTimePoints (worm_formats.hpp): a WCON parsed once through nlohmann::json's SAX interface,
// its per-time arrays spooled to anonymous temporary files and read back a time point at a time.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/trajectory/worm_formats.hpp"
#include "wcon_units.hpp"

namespace owval {
namespace {
using nlohmann::json;

enum Array { kT, kCx, kCy, kOx, kOy, kX, kY, kArrays };
constexpr const char* kArrayName[kArrays] = {"t", "cx", "cy", "ox", "oy", "x", "y"};

std::optional<Array> ArrayNamed(const std::string& key) {
  for (int a = 0; a < kArrays; ++a)
    if (key == kArrayName[a]) return Array(a);
  return std::nullopt;
}

// Doubles written one after another to an anonymous temporary file (gone with the process), then
// read back in the same order.
class Spool {
 public:
  ~Spool() {
    if (file_) std::fclose(file_);
  }
  void Put(double value, const std::string& name) {
    if (!file_) file_ = std::tmpfile();
    if (!file_ || std::fwrite(&value, sizeof value, 1, file_) != 1)
      throw InputError(name, 0, "cannot write a temporary file");
  }
  void Rewind() {
    if (file_) std::rewind(file_);
  }
  double Get(const std::string& name) {
    double value = 0;
    if (!file_ || std::fread(&value, sizeof value, 1, file_) != 1)
      throw InputError(name, 0, "cannot read a temporary file");
    return value;
  }

 private:
  std::FILE* file_ = nullptr;
};

// One record of the data block: what it holds, not its values (those are spooled).
struct Record {
  std::optional<std::string> id;
  bool present[kArrays] = {};
  std::size_t count[kArrays] = {};  // elements; for x and y, rows
};

}  // namespace

struct WconTimePoints::Parsed : json::json_sax_t {
  explicit Parsed(std::string file) : name(std::move(file)) {}

  // Where the parser is: what the innermost open object or array is.
  enum class Kind { kRoot, kUnits, kData, kRecord, kFlat, kNested, kRow, kSkip };
  struct Level {
    Kind kind;
    Array array = kT;  // kFlat, kNested, kRow
  };

  std::string name, last_key;  // the key whose value comes next
  std::vector<Level> levels;
  bool saw_data = false, saw_units = false, units_is_object = false;
  std::map<std::string, std::optional<std::string>> units;  // nullopt: not a string
  std::vector<Record> records;
  Spool spools[kArrays];
  std::vector<double> row;  // the x or y row being parsed

  // After parsing: what Next() reads.
  double t_factor = 1, x_factor = 1, y_factor = 1, cx_factor = 1, cy_factor = 1;
  bool centroid = false;
  std::size_t size = 0, record = 0, element = 0, points = 0;
  double last_time_s = 0;

  [[noreturn]] void Fail(const std::string& what) const { throw InputError(name, 0, what); }
  std::string At() const { return "data[" + std::to_string(records.size() - 1) + "]."; }
  Kind Top() const { return levels.empty() ? Kind::kSkip : levels.back().kind; }

  [[noreturn]] void NotANumber() const {
    const Array a = levels.back().array;
    Fail(At() + kArrayName[a] + ": expected numbers (null and non-numbers unsupported)");
  }

  [[noreturn]] void NotARecord() const {
    Fail("data[" + std::to_string(records.size() - 1) + "]: expected a record with id, t, x and y");
  }

  // A number, a string, a bool or null where the innermost level is.
  bool Value(std::optional<double> number, const std::string* text) {
    const Kind top = Top();
    if (top == Kind::kFlat || top == Kind::kNested || top == Kind::kRow) {
      if (!number) NotANumber();
      const Array a = levels.back().array;
      if (top == Kind::kRow) {
        row.push_back(*number);
      } else {
        if (top == Kind::kNested) spools[a].Put(1, name);  // a single point: a row of one
        spools[a].Put(*number, name);
        ++records.back().count[a];
      }
    } else if (top == Kind::kData) {
      records.emplace_back();
      NotARecord();
    } else if (top == Kind::kUnits) {
      units[last_key] = text ? std::optional<std::string>(*text) : std::nullopt;
    } else if (top == Kind::kRecord && last_key == "id") {
      if (!text) Fail(At() + "id: expected a string");
      records.back().id = *text;
    } else if (top == Kind::kRecord && ArrayNamed(last_key)) {
      Fail(At() + last_key + ": expected an array of numbers");
    } else if (top == Kind::kRoot && (last_key == "units" || last_key == "data")) {
      Fail(last_key == "units" ? "units: expected an object"
                               : "data: expected a record or an array of records");
    }
    return true;
  }
  bool null() override { return Value(std::nullopt, nullptr); }
  bool boolean(bool) override { return Value(std::nullopt, nullptr); }
  bool number_integer(number_integer_t v) override { return Value(double(v), nullptr); }
  bool number_unsigned(number_unsigned_t v) override { return Value(double(v), nullptr); }
  bool number_float(number_float_t v, const string_t&) override { return Value(v, nullptr); }
  bool string(string_t& v) override { return Value(std::nullopt, &v); }
  bool binary(binary_t&) override { return Value(std::nullopt, nullptr); }
  bool key(string_t& k) override {
    last_key = k;
    return true;
  }

  // An object or array opens where the innermost level is.
  Level Opened(bool is_object) {
    const Kind top = Top();
    if (levels.empty()) return {is_object ? Kind::kRoot : Kind::kSkip};
    if (top == Kind::kFlat || top == Kind::kRow) NotANumber();
    if (top == Kind::kNested) {
      if (is_object) NotANumber();
      row.clear();
      return {Kind::kRow, levels.back().array};
    }
    if (top == Kind::kRoot && last_key == "units") {
      saw_units = true;
      units_is_object = is_object;
      return {is_object ? Kind::kUnits : Kind::kSkip};
    }
    if (top == Kind::kRoot && last_key == "data") {
      saw_data = true;
      if (!is_object) return {Kind::kData};
      records.emplace_back();
      return {Kind::kRecord};
    }
    if (top == Kind::kData) {
      records.emplace_back();
      if (!is_object) NotARecord();
      return {Kind::kRecord};
    }
    if (top == Kind::kRecord && last_key == "id") Fail(At() + "id: expected a string");
    if (top == Kind::kRecord && ArrayNamed(last_key)) {
      const Array a = *ArrayNamed(last_key);
      if (is_object) Fail(At() + last_key + ": expected an array of numbers");
      records.back().present[a] = true;
      return {a == kX || a == kY ? Kind::kNested : Kind::kFlat, a};
    }
    if (top == Kind::kUnits) units[last_key] = std::nullopt;
    return {Kind::kSkip};
  }
  bool start_object(std::size_t) override {
    levels.push_back(Opened(true));
    return true;
  }
  bool start_array(std::size_t) override {
    levels.push_back(Opened(false));
    return true;
  }
  bool Closed() {
    const Level closed = levels.back();
    levels.pop_back();
    if (closed.kind == Kind::kRow) {
      spools[closed.array].Put(double(row.size()), name);
      for (double v : row) spools[closed.array].Put(v, name);
      ++records.back().count[closed.array];
    }
    if (closed.kind == Kind::kRecord) CheckRecord();
    return true;
  }
  bool end_object() override { return Closed(); }
  bool end_array() override { return Closed(); }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& e) override {
    Fail("not JSON at byte " + std::to_string(position) + ": " + e.what());
  }

  // What ReadWcon refuses of a record, said the same way.
  void CheckRecord() const {
    const Record& r = records.back();
    const std::string at = At();
    if (!r.id || !r.present[kT] || !r.present[kX] || !r.present[kY]) NotARecord();
    const std::size_t n = r.count[kT];
    if (n == 0) Fail(at + "t: must not be empty");
    if (r.count[kX] != n || r.count[kY] != n) Fail(at + "x/y: expected one array per time point");
    if ((r.present[kOx] && r.count[kOx] != n) || (r.present[kOy] && r.count[kOy] != n))
      Fail(at + "ox/oy: one per time");
    if (r.present[kCx] != r.present[kCy]) Fail(at + "cx/cy: must come in pairs");
    if (r.present[kCx] && (r.count[kCx] != n || r.count[kCy] != n))
      Fail(at + "cx/cy: one per time");
  }

  double Unit(const char* unit, bool length) const {
    const auto it = units.find(unit);
    if (it == units.end() || !it->second)
      Fail(std::string("units.") + unit + ": expected a unit string");
    const double f = length ? WconLengthFactor(*it->second) : WconTimeFactor(*it->second);
    if (f == 0) Fail(std::string("units.") + unit + ": unsupported unit \"" + *it->second + "\"");
    return f;
  }

  // The units and the first id's records, once the whole file is parsed.
  void Finish() {
    if (!saw_units || !saw_data) Fail("expected a WCON object with \"units\" and \"data\"");
    if (!units_is_object) Fail("units: expected an object");
    t_factor = Unit("t", false);
    x_factor = Unit("x", true);
    y_factor = Unit("y", true);
    if (records.empty()) Fail("data: no time point");
    centroid = records.front().present[kCx];
    if (centroid) {
      cx_factor = Unit("cx", true);
      cy_factor = Unit("cy", true);
    }
    for (std::size_t i = 0; i < records.size(); ++i) {
      if (records[i].id != records.front().id) continue;
      if (records[i].present[kCx] != centroid)
        Fail("data[" + std::to_string(i) + "].cx/cy: in some of the id's records only");
      size += records[i].count[kT];
    }
    for (Spool& s : spools) s.Rewind();
  }

  template <typename Stored>
  Stored Millimetres(double value_mm, const std::string& field) const {
    return WconMillimetres<Stored>(value_mm, name, field);
  }

  std::vector<double> Row(Array a) {
    const double n = spools[a].Get(name);
    std::vector<double> values(static_cast<std::size_t>(n));
    for (double& v : values) v = spools[a].Get(name);
    return values;
  }

  // The element's values of every array the record holds are read, whether kept or not.
  void ReadElement(const Record& r, bool keep, WconTimePoint* p) {
    double value[kArrays] = {};
    for (int a = kT; a <= kOy; ++a)
      if (r.present[a]) value[a] = spools[a].Get(name);
    const std::vector<double> x = Row(kX), y = Row(kY);
    if (!keep) return;
    const std::string w =
        "data[" + std::to_string(record) + "].x/y[" + std::to_string(element) + "]";
    if (x.size() != y.size() || x.empty()) Fail(w + ": x and y must be equal in length");
    p->time_s = value[kT] * t_factor;
    p->x_mm.clear();
    p->y_mm.clear();
    for (std::size_t k = 0; k < x.size(); ++k) {
      p->x_mm.push_back(Millimetres<float>((x[k] + value[kOx]) * x_factor, w));
      p->y_mm.push_back(Millimetres<float>((y[k] + value[kOy]) * y_factor, w));
    }
    const std::string c =
        "data[" + std::to_string(record) + "].cx/cy[" + std::to_string(element) + "]";
    p->cx_mm = centroid ? Millimetres<double>((value[kCx] + value[kOx]) * cx_factor, c) : 0;
    p->cy_mm = centroid ? Millimetres<double>((value[kCy] + value[kOy]) * cy_factor, c) : 0;
  }
};

WconTimePoints::WconTimePoints(const std::filesystem::path& path)
    : parsed_(std::make_unique<Parsed>(path.string())) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open");
  try {
    json::sax_parse(in, parsed_.get());
  } catch (const json::exception& e) {  // a number beyond a double's range (1e400)
    throw InputError(path.string(), 0, std::string("not a WCON number: ") + e.what());
  }
  parsed_->Finish();
}

WconTimePoints::~WconTimePoints() = default;

std::size_t WconTimePoints::size() const { return parsed_->size; }
bool WconTimePoints::has_centroid() const { return parsed_->centroid; }

bool WconTimePoints::Next(WconTimePoint* point) {
  Parsed& p = *parsed_;
  while (p.record < p.records.size()) {
    const Record& r = p.records[p.record];
    if (p.element == r.count[kT]) {
      ++p.record, p.element = 0;
      continue;
    }
    const bool keep = r.id == p.records.front().id;
    p.ReadElement(r, keep, point);
    ++p.element;
    if (!keep) continue;
    if (!std::isfinite(point->time_s) || (p.points > 0 && !(point->time_s > p.last_time_s)))
      p.Fail("data: t: time point " + std::to_string(p.points) + " at " +
             FormatNumber(point->time_s) + " s is not finite and after its predecessor's");
    p.last_time_s = point->time_s;
    ++p.points;
    return true;
  }
  return false;
}

}  // namespace owval
