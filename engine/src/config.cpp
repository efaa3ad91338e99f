// Sibernetic's configuration format: reading (with Sibernetic's own parsing rules where they
// matter, see sibernetic_physics.md §1-2) and writing.
#include "owval/engine/config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <regex>
#include <sstream>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/memory_budget.hpp"

namespace owval::engine {
namespace {

enum class Section {
  kNone,
  kPhysical,
  kBox,
  kPosition,
  kVelocity,
  kConnection,
  kMembranes,
  kMemIndex,
  kEnd
};

Section SectionOf(const std::string& line) {
  static const std::pair<const char*, Section> names[] = {
      {"[physical parameters]", Section::kPhysical},
      {"[simulation box]", Section::kBox},
      {"[position]", Section::kPosition},
      {"[velocity]", Section::kVelocity},
      {"[connection]", Section::kConnection},
      {"[membranes]", Section::kMembranes},
      {"[particleMemIndex]", Section::kMemIndex},
      {"[end]", Section::kEnd}};
  for (const auto& [name, section] : names)
    if (line == name) return section;
  return Section::kNone;
}

constexpr std::size_t kMaxParameterLineChars = 1024;

class Reader {
 public:
  Reader(const std::string& name) : name_(name) {}

  // Up to `count` numbers of a TAB/space separated row; a short row repeats its last field into
  // the missing ones, as Sibernetic's loader does (owHelper.cpp).
  std::array<float, 4> Row(const std::string& line, std::size_t count, const char* what) const {
    std::array<float, 4> row{};
    std::size_t n = 0;
    const char* p = line.data();
    const char* end = p + line.size();
    while (p < end && n < 4) {
      while (p < end && (*p == ' ' || *p == '\t')) ++p;
      if (p >= end) break;
      const char* start = p;
      if (*p == '+') ++p;
      auto [next, ec] = std::from_chars(p, end, row[n]);
      if (ec != std::errc() || (next < end && *next != ' ' && *next != '\t')) {
        const char* stop = start;
        while (stop < end && *stop != ' ' && *stop != '\t') ++stop;
        Fail(std::string("expected a number in the ") + what + " row, found '" +
             std::string(start, stop) + "'");
      }
      if (!std::isfinite(row[n])) Fail(std::string("non-finite number in the ") + what + " row");
      p = next;
      ++n;
    }
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (p < end)
      Fail(std::string("too many fields in the ") + what + " row (expected " +
           std::to_string(count) + ")");
    if (n == 0) Fail(std::string("empty ") + what + " row");
    for (std::size_t i = n; i < 4; ++i) row[i] = row[n - 1];
    return row;
  }

  [[noreturn]] void Fail(const std::string& what) const { throw InputError(name_, line_, what); }
  std::size_t line_ = 0;

 private:
  std::string name_;
};

// Sibernetic's kernels take a particle's class as (int)w and know 1, 2 and 3 only; any other
// class would move as none of them (and (int) of 1e30 is undefined). A row with three fields
// reads its third as the type (Sibernetic's loader repeats the last field), so the message says
// how many fields a row needs.
void CheckTypeCode(const Reader& reader, float type) {
  if (!(type >= 1.0f && type < 4.0f))
    reader.Fail("[position] row has type " + FormatNumber(type) +
                ": expected x, y, z and a type 1.x (liquid), 2.x (elastic) or 3.x (boundary)");
}

// Sibernetic accepts "name: value" where value is an unsigned decimal that may carry an exponent
// only after a decimal point, with an optional trailing // comment (owHelper.cpp:83-91).
void ParsePhysicalParameter(const std::string& line, const Reader& reader,
                            SiberneticConfig* config) {
  // std::regex matches recursively: a 100,000-character line would overflow the stack.
  if (line.size() > kMaxParameterLineChars)
    reader.Fail("[physical parameters] line longer than " + std::to_string(kMaxParameterLineChars) +
                " characters");
  static const std::regex rule(
      R"(^\s*([A-Za-z_][A-Za-z0-9_]*)\s*:\s*([0-9]+(\.[0-9]*([eE][-+]?[0-9]+)?)?)\s*(//.*)?$)");
  std::smatch m;
  if (!std::regex_match(line, m, rule)) return;
  const double value = std::strtod(m[2].str().c_str(), nullptr);  // no throw on 1.0e999
  if (!std::isfinite(value))
    reader.Fail("[physical parameters] " + m[1].str() + " is not a finite number");
  config->physical_parameters.emplace(m[1].str(), value);
}

// C truncation, as the kernels do; a value no int holds (1e30) is refused, not converted.
int ToIndex(const Reader& reader, float v, const char* what) {
  if (!(v > -2147483648.0f && v < 2147483648.0f))
    reader.Fail(std::string(what) + " " + std::to_string(v) +
                " is not a particle or membrane index");
  return static_cast<int>(v);
}

// [simulation box]: finite (the reader refuses NaN and Inf), not inverted, and small enough that
// the neighbour grid over it fits in memory.
void ValidateBox(const Box& b, const std::string& name) {
  if (b.xmax < b.xmin || b.ymax < b.ymin || b.zmax < b.zmin)
    throw InputError(name, 0, "[simulation box]: a maximum is below its minimum");
  const PhysicsConstants defaults;
  const std::size_t cells = NeighbourGridCells(b, defaults.h_cu);
  const std::size_t limit = std::min<std::size_t>(std::numeric_limits<int>::max(),
                                                  MemoryBudgetBytes() / kNeighbourGridBytesPerCell);
  // NeighbourGridCells saturates: SIZE_MAX means "more than it can count", not that number.
  const std::string count =
      cells == std::numeric_limits<std::size_t>::max() ? "more than 10^19" : std::to_string(cells);
  if (cells > limit)
    throw InputError(name, 0,
                     "[simulation box] " + std::to_string(b.xmax) + " x " + std::to_string(b.ymax) +
                         " x " + std::to_string(b.zmax) + " cu needs a neighbour grid of " + count +
                         " cells (2h = " + std::to_string(2 * defaults.h_cu) +
                         " cu each), over the limit of " + std::to_string(limit) +
                         " (memory budget, --max-memory)");
}

// [membranes] and [particleMemIndex]: every index names something that exists.
void ValidateMembranes(const SiberneticConfig& c, const std::string& name, std::size_t elastic) {
  for (const auto& m : c.membranes)
    for (int v : m)
      if (v < 0 || static_cast<std::size_t>(v) >= elastic)
        throw InputError(name, 0,
                         "membrane vertex " + std::to_string(v) + " is not an elastic particle");
  if (!c.membranes.empty() && c.particle_mem_index.empty())
    throw InputError(name, 0,
                     "[membranes] without [particleMemIndex]: expected 7 membrane slots per "
                     "elastic particle");
  for (std::size_t r = 0; r < c.particle_mem_index.size(); ++r) {
    const int m = c.particle_mem_index[r];
    if (m < -1 || (m >= 0 && static_cast<std::size_t>(m) >= c.membranes.size()))
      throw InputError(name, 0,
                       "[particleMemIndex] row " + std::to_string(r) + " names membrane " +
                           std::to_string(m) + ", which does not exist (" +
                           std::to_string(c.membranes.size()) + " membranes; -1 = none)");
  }
}

void Validate(const SiberneticConfig& c, const std::string& name, bool box_seen, bool end_seen,
              std::size_t lines) {
  if (!box_seen)
    throw InputError(name, 0,
                     "missing [simulation box] section (6 lines: xmin xmax ymin ymax zmin zmax)");
  if (!end_seen) throw InputError(name, lines, "truncated configuration: expected an [end] line");
  if (c.position.empty()) throw InputError(name, 0, "no [position] rows");
  if (c.velocity.size() != c.position.size())
    throw InputError(name, 0,
                     "wrong particle count: " + std::to_string(c.position.size()) +
                         " [position] rows but " + std::to_string(c.velocity.size()) +
                         " [velocity] rows");
  // Every [position] row's type was checked where it was read (CheckTypeCode).
  const std::size_t elastic = c.elastic_count();
  for (std::size_t i = 0; i < elastic; ++i)
    if (KindOf(c.position[i][3]) != ParticleKind::kElastic)
      throw InputError(name, 0,
                       "elastic particles must come first: row " + std::to_string(i) +
                           " of [position] has type " + std::to_string(c.position[i][3]) +
                           " but there are " + std::to_string(elastic) + " elastic particles");
  if (elastic > 0 && c.connection.size() != elastic * kConnectionSlots)
    throw InputError(name, 0,
                     "[connection] has " + std::to_string(c.connection.size()) +
                         " rows, expected 32 per elastic particle (" +
                         std::to_string(elastic * kConnectionSlots) + ")");
  for (std::size_t r = 0; r < c.connection.size(); ++r) {
    const float partner = c.connection[r][0];
    // Truncation: int(partner) >= n exactly when partner >= n, and no cast of 1e30 is made.
    if (partner >= 0 && !(c.connection[r][1] >= 0))
      throw InputError(name, 0,
                       "connection row " + std::to_string(r) + " has rest length " +
                           FormatNumber(c.connection[r][1]) + " cu: expected 0 or more");
    if (partner >= static_cast<float>(c.particle_count()))
      throw InputError(name, 0,
                       "connection row " + std::to_string(r) + " links to particle " +
                           std::to_string(partner) + ", which does not exist (" +
                           std::to_string(c.particle_count()) + " particles)");
  }
  if (!c.particle_mem_index.empty() &&
      c.particle_mem_index.size() != elastic * kMembraneSlotsPerParticle)
    throw InputError(name, 0,
                     "[particleMemIndex] has " + std::to_string(c.particle_mem_index.size()) +
                         " rows, expected 7 per elastic particle (" + std::to_string(elastic * 7) +
                         ")");
  ValidateMembranes(c, name, elastic);
  ValidateBox(c.box, name);
}

}  // namespace

std::size_t NeighbourGridCells(const Box& box, double h_cu) {
  // As NeighbourGrid sizes itself: (int)(max / 2h) + 2 cells per axis from 0 (sphFluid.cl:142).
  auto axis = [&](float upper) {
    const double cells = std::floor(std::max(double(upper), 0.0) / (2.0 * h_cu)) + 2.0;
    return cells < 1e18 ? static_cast<std::size_t>(cells) : std::numeric_limits<std::size_t>::max();
  };
  return SaturatingProduct(SaturatingProduct(axis(box.xmax), axis(box.ymax)), axis(box.zmax));
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> ConnectionPairs(
    const SiberneticConfig& config) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t row = 0; row < config.connection.size(); ++row)
    if (config.connection[row][0] >= 0)
      pairs.emplace_back(std::uint32_t(row / kConnectionSlots),
                         std::uint32_t(config.connection[row][0]));
  return pairs;
}

std::size_t SiberneticConfig::elastic_count() const {
  std::size_t n = 0;
  for (const Row4& p : position) n += KindOf(p[3]) == ParticleKind::kElastic;
  return n;
}
std::size_t SiberneticConfig::liquid_count() const {
  std::size_t n = 0;
  for (const Row4& p : position) n += KindOf(p[3]) == ParticleKind::kLiquid;
  return n;
}
std::size_t SiberneticConfig::boundary_count() const {
  return position.size() - elastic_count() - liquid_count();
}

SiberneticConfig ParseSiberneticConfig(const std::string& text, const std::string& name) {
  SiberneticConfig c;
  c.source = name;
  Reader reader(name);
  std::istringstream in(text);
  Section section = Section::kNone;
  std::vector<float> box;
  bool box_seen = false, end_seen = false;
  for (std::string line; std::getline(in, line);) {
    ++reader.line_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    if (line[0] == '[') {
      section = SectionOf(line);
      if (section == Section::kNone) reader.Fail("unknown section '" + line + "'");
      if (section == Section::kBox) box_seen = true;
      if (section == Section::kEnd) end_seen = true;
      continue;
    }
    switch (section) {
      case Section::kNone:
        reader.Fail(
            "data before the first section header (a file older than the \"[simulation box]\" "
            "header: Sibernetic 8d2df73 needs that line before the 6 box values too)");
        break;
      case Section::kPhysical:
        ParsePhysicalParameter(line, reader, &c);
        break;
      case Section::kBox:
        if (box.size() == 6) reader.Fail("[simulation box] holds 6 lines, found a 7th");
        box.push_back(reader.Row(line, 1, "simulation box")[0]);
        break;
      case Section::kPosition:
        c.position.push_back(reader.Row(line, 4, "position"));
        CheckTypeCode(reader, c.position.back()[3]);  // here, where the line is known
        break;
      case Section::kVelocity:
        c.velocity.push_back(reader.Row(line, 4, "velocity"));
        break;
      case Section::kConnection:
        c.connection.push_back(reader.Row(line, 4, "connection"));
        break;
      case Section::kMembranes: {
        const auto r = reader.Row(line, 3, "membrane");
        c.membranes.push_back({ToIndex(reader, r[0], "membrane vertex"),
                               ToIndex(reader, r[1], "membrane vertex"),
                               ToIndex(reader, r[2], "membrane vertex")});
        break;
      }
      case Section::kMemIndex:
        c.particle_mem_index.push_back(
            ToIndex(reader, reader.Row(line, 1, "particleMemIndex")[0], "particleMemIndex"));
        break;
      case Section::kEnd:
        break;  // Sibernetic stops reading at [end]
    }
    if (section == Section::kEnd) break;
  }
  if (box_seen && box.size() != 6)
    throw InputError(name, 0,
                     "[simulation box] needs 6 numbers, found " + std::to_string(box.size()));
  if (box_seen) c.box = {box[0], box[1], box[2], box[3], box[4], box[5]};
  Validate(c, name, box_seen, end_seen, reader.line_);
  return c;
}

SiberneticConfig ReadSiberneticConfig(const std::filesystem::path& path) {
  return ParseSiberneticConfig(ReadWholeFile(path), path.string());
}

namespace {
void AppendRow(std::ostringstream& out, const float* v, int n) {
  for (int i = 0; i < n; ++i) {
    char buffer[32];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v[i]);  // shortest round-trip
    out.write(buffer, end - buffer);
    out << (i + 1 < n ? '\t' : '\n');
  }
}
}  // namespace

void WriteSiberneticConfig(const SiberneticConfig& c, const std::filesystem::path& path) {
  std::ostringstream out;
  if (!c.physical_parameters.empty()) {
    out << "[physical parameters]\n";
    for (const auto& [k, v] : c.physical_parameters) out << k << ": " << v << "\n";
  }
  out << "[simulation box]\n";
  for (float v : {c.box.xmin, c.box.xmax, c.box.ymin, c.box.ymax, c.box.zmin, c.box.zmax})
    AppendRow(out, &v, 1);
  out << "[position]\n";
  for (const Row4& r : c.position) AppendRow(out, r.data(), 4);
  out << "[velocity]\n";
  for (const Row4& r : c.velocity) AppendRow(out, r.data(), 4);
  out << "[connection]\n";
  for (const Row4& r : c.connection) AppendRow(out, r.data(), 4);
  out << "[membranes]\n";
  for (const auto& m : c.membranes) out << m[0] << '\t' << m[1] << '\t' << m[2] << '\n';
  out << "[particleMemIndex]\n";
  for (int i : c.particle_mem_index) out << i << '\n';
  out << "[end]\n";
  WriteFileAtomically(path, out.str());
}

}  // namespace owval::engine
