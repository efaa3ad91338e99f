// WconReader (worm_formats.hpp): a WCON parsed once through nlohmann::json's SAX interface,
// its per-time arrays spooled to anonymous temporary files and read back a time point at a time,
// its metadata kept.
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <utility>

#include "frame_times.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/input_file.hpp"
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

// The file's bytes for the parser, read 64 KiB at a time. The parser says where it stopped as a
// byte index; the lines are counted here as the bytes go by, so that index can be said as a line
// and column without holding the file (the parser reads at most one byte past it).
class CountedBytes {
 public:
  CountedBytes(std::FILE* file, const std::string& name) : file_(file), name_(name) {}
  bool AtEnd() { return next_ == end_ && !Fill(); }
  const char& Current() const { return *next_; }
  void Advance() {
    ++delivered_;
    if (*next_ == '\n') newline_at_[++newlines_ % kRecent] = delivered_;
    ++next_;
  }
  // Line (from 1) and column (bytes from 1) of the byte at index `byte` (from 1, as
  // nlohmann::json::parse_error::byte; the end of the file is the index after its last byte).
  // Column 0 when the byte lies further back than the newlines remembered.
  std::pair<std::size_t, std::size_t> LineAndColumn(std::size_t byte) const {
    std::size_t before = newlines_;  // newlines before `byte`
    for (std::size_t k = newlines_; k > 0 && k + kRecent > newlines_; --k, --before)
      if (newline_at_[k % kRecent] < byte) return {before + 1, byte - newline_at_[k % kRecent]};
    return {before + 1, before == 0 ? byte : 0};
  }

 private:
  static constexpr std::size_t kRecent = 4;
  bool Fill() {
    const std::size_t n = std::fread(buffer_, 1, sizeof buffer_, file_);
    if (n == 0 && std::ferror(file_)) throw InputError(name_, 0, "cannot read");
    next_ = buffer_, end_ = buffer_ + n;
    return n > 0;
  }
  std::FILE* file_;
  const std::string& name_;
  char buffer_[1 << 16];
  const char *next_ = buffer_, *end_ = buffer_;
  std::size_t delivered_ = 0, newlines_ = 0;
  std::size_t newline_at_[kRecent] = {};  // the index (from 1) of the last newlines
};

// CountedBytes as the input iterator json::sax_parse reads; the default one is the end.
class ByteIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;
  ByteIterator() = default;
  explicit ByteIterator(CountedBytes* bytes) : bytes_(bytes) {}
  reference operator*() const { return bytes_->Current(); }
  ByteIterator& operator++() {
    bytes_->Advance();
    return *this;
  }
  bool operator==(const ByteIterator& other) const { return AtEnd() == other.AtEnd(); }
  bool operator!=(const ByteIterator& other) const { return !(*this == other); }

 private:
  bool AtEnd() const { return !bytes_ || bytes_->AtEnd(); }
  CountedBytes* bytes_ = nullptr;
};

// nlohmann's what() without its tag and its own position ("[json.exception.parse_error.101]
// parse error at line 1, column 2: "): the reader says the position as FILE:LINE:COLUMN.
std::string JsonReason(const std::string& what) {
  std::string reason = what;
  if (reason.rfind("[json.exception.", 0) == 0 && reason.find("] ") != std::string::npos)
    reason = reason.substr(reason.find("] ") + 2);
  if (reason.rfind("parse error", 0) == 0 && reason.find(": ") != std::string::npos)
    reason = reason.substr(reason.find(": ") + 2);
  return reason;
}

// A subtree of the document built from its events (metadata.software.settings, "@owval"): a
// later key of the same name replaces an earlier one, as json::parse does.
class JsonCapture {
 public:
  void Start(json* destination) {
    destination_ = destination;
    open_.clear();
  }
  void Add(json value, const std::string& key) { Place(key) = std::move(value); }
  void Open(bool is_object, const std::string& key) {
    json& container = Place(key);
    container = is_object ? json::object() : json::array();
    open_.push_back(&container);
  }
  void Close() { open_.pop_back(); }

 private:
  // Where the next value goes: the destination, or the innermost open container.
  json& Place(const std::string& key) {
    if (open_.empty()) return *destination_;
    json& top = *open_.back();
    if (top.is_array()) return top.emplace_back();
    return top[key];
  }
  json* destination_ = nullptr;
  std::vector<json*> open_;  // ancestors only: a container's children are added when it is top
};

}  // namespace

struct WconReader::Parsed : json::json_sax_t {
  explicit Parsed(std::string file) : name(std::move(file)) {}

  // Where the parser is: what the innermost open object or array is.
  enum class Kind {
    kRoot,
    kUnits,
    kData,
    kRecord,
    kFlat,
    kNested,
    kRow,
    kMetadata,
    kSoftware,  // "metadata" and its "software"
    kCapture,   // within "@owval" or metadata.software.settings, kept whole
    kSkip
  };
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
  WormTrack head;           // id, software version and settings, "@owval"
  JsonCapture capture;
  CountedBytes* bytes = nullptr;  // while parsing: where a syntax error is

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

  // metadata.software's version and settings as a document without them has them.
  void ForgetSoftware() {
    head.software_version.clear();
    head.software_settings = json::object();
  }

  // A value kept with the metadata; false when it is not one.
  bool Metadata(json* value) {
    const Kind top = Top();
    if (top == Kind::kCapture) {
      capture.Add(std::move(*value), last_key);
    } else if (top == Kind::kRoot && last_key == "@owval") {
      head.owval = std::move(*value);
    } else if (top == Kind::kSoftware && last_key == "settings") {
      head.software_settings = std::move(*value);
    } else if (top == Kind::kSoftware && last_key == "version") {
      head.software_version = value->is_string() ? value->get<std::string>() : "";
    } else if ((top == Kind::kRoot && last_key == "metadata") ||
               (top == Kind::kMetadata && last_key == "software")) {
      ForgetSoftware();  // not an object: a later one replaces an earlier, as json::parse does
    } else {
      return false;
    }
    return true;
  }

  // A number, a string, a bool or null where the innermost level is.
  bool Value(json value) {
    const Kind top = Top();
    const std::optional<double> number =
        value.is_number() ? std::optional<double>(value.get<double>()) : std::nullopt;
    const std::string* text = value.is_string() ? &value.get_ref<const std::string&>() : nullptr;
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
    } else {
      Metadata(&value);
    }
    return true;
  }
  bool null() override { return Value(nullptr); }
  bool boolean(bool v) override { return Value(v); }
  bool number_integer(number_integer_t v) override { return Value(v); }
  bool number_unsigned(number_unsigned_t v) override { return Value(v); }
  bool number_float(number_float_t v, const string_t&) override { return Value(v); }
  bool string(string_t& v) override { return Value(v); }
  bool binary(binary_t& v) override { return Value(json::binary(v)); }
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
    return MetadataOpened(is_object);
  }

  // An object or array opening within the metadata, or skipped.
  Level MetadataOpened(bool is_object) {
    const Kind top = Top();
    if (top == Kind::kCapture) {
      capture.Open(is_object, last_key);
      return {Kind::kCapture};
    }
    const bool owval = top == Kind::kRoot && last_key == "@owval";
    const bool settings = top == Kind::kSoftware && last_key == "settings";
    if (owval || settings) {
      capture.Start(owval ? &head.owval : &head.software_settings);
      capture.Open(is_object, last_key);
      return {Kind::kCapture};
    }
    if (top == Kind::kRoot && last_key == "metadata") {
      ForgetSoftware();
      return {is_object ? Kind::kMetadata : Kind::kSkip};
    }
    if (top == Kind::kMetadata && last_key == "software") {
      ForgetSoftware();
      return {is_object ? Kind::kSoftware : Kind::kSkip};
    }
    if (top == Kind::kSoftware && last_key == "version") head.software_version.clear();
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
    if (closed.kind == Kind::kCapture) capture.Close();
    return true;
  }
  bool end_object() override { return Closed(); }
  bool end_array() override { return Closed(); }
  // A syntax error, or a number beyond a double's range (1e400), where the parser stopped.
  bool parse_error(std::size_t byte, const std::string&,
                   const nlohmann::detail::exception& e) override {
    if (!bytes) Fail("not valid JSON: " + JsonReason(e.what()));
    const auto [line, column] = bytes->LineAndColumn(byte);
    // FILE:LINE:COLUMN, as compilers say it (InputError itself carries no column).
    throw InputError(name + ":" + std::to_string(line) + ":" + std::to_string(column) +
                     ": not valid JSON: " + JsonReason(e.what()));
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
    head.id = *records.front().id;
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

WconReader::WconReader(const std::filesystem::path& path)
    : parsed_(std::make_unique<Parsed>(path.string())) {
  RequireInputFile(path, "a WCON file");  // before fopen(): a FIFO would block it
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  if (!file) throw InputError(path.string(), 0, "cannot open");
  CountedBytes bytes(file.get(), parsed_->name);
  parsed_->bytes = &bytes;
  try {
    json::sax_parse(ByteIterator(&bytes), ByteIterator(), parsed_.get());
  } catch (const json::exception& e) {  // the parser's own errors go to parse_error; any other
    throw InputError(path.string(), 0, "not valid JSON: " + JsonReason(e.what()));
  }
  parsed_->bytes = nullptr;
  parsed_->Finish();
}

WconReader::~WconReader() = default;

const WormTrack& WconReader::head() const { return parsed_->head; }
std::size_t WconReader::size() const { return parsed_->size; }
bool WconReader::has_centroid() const { return parsed_->centroid; }

void WconReader::Rewind() {
  Parsed& p = *parsed_;
  for (Spool& s : p.spools) s.Rewind();
  p.record = p.element = p.points = 0;
  p.last_time_s = 0;
}

bool WconReader::Next(WconTimePoint* point) {
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
    // Finite too: a t of 1e308 in hours is infinite in seconds.
    CheckFrameTimeFollows(p.points, point->time_s, p.last_time_s, p.name, "data: t: ");
    p.last_time_s = point->time_s;
    ++p.points;
    return true;
  }
  return false;
}

}  // namespace owval
