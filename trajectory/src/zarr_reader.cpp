// OmeZarrReader (worm_formats.hpp): zarr-specs v2, .zarray metadata and one file per chunk named
// "i.j.k" ("." separator), read back for checking a store against its trajectory.
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/base/input_file.hpp"
#include "owval/base/json_file.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/trajectory/worm_formats.hpp"
#include "wcon_units.hpp"

namespace owval {
namespace fs = std::filesystem;
using json = nlohmann::json;
namespace {

std::string ReadBytes(const fs::path& path) {
  RequireInputFile(path);  // before open(): a FIFO in the store would block it
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct ArrayMeta {
  std::vector<std::size_t> shape, chunks;
  std::string compressor;  // "zlib" or ""
  double fill_value = 0;
};

// A .zarray's `key`: `rank` whole numbers (as integers, or floats such as 1e15 below 2^63).
// nlohmann's get<std::vector<std::size_t>>() threw its own "type must be number, but is string"
// and converted 1e300 to an integer unchecked (UBSan float-cast-overflow).
std::vector<std::size_t> Dimensions(const json& m, const char* key, std::size_t rank,
                                    const fs::path& file) {
  const auto refused = [&] {
    return InputError(
        file.string(), 0,
        std::string(key) + ": expected " + std::to_string(rank) + " whole numbers (dimensions)");
  };
  if (!m.contains(key) || !m[key].is_array() || m[key].size() != rank) throw refused();
  std::vector<std::size_t> sizes;
  for (const json& v : m[key]) {
    if (v.is_number_unsigned()) {
      sizes.push_back(v.get<std::size_t>());
      continue;
    }
    // A whole number written as 1e3 or 1000.0 is one; converted only once it is in range.
    const double d = v.is_number_float() ? v.get<double>() : -1;
    if (!(d >= 0 && d < 0x1p63 && d == std::floor(d))) throw refused();
    sizes.push_back(static_cast<std::size_t>(d));
  }
  return sizes;
}

// The array's .zarray, checked against what this reader can read: `dtype`, C order, no filters,
// "." separator, zlib or no compressor, `rank` dimensions. Every field of another type than
// zarr's is refused naming the field (json::value() threw nlohmann's type_error, not ours).
ArrayMeta ReadMeta(const fs::path& array, const char* dtype, std::size_t rank) {
  const fs::path file = array / ".zarray";
  auto fail = [&](const std::string& what) { throw InputError(file.string(), 0, what); };
  const json m = ParseJsonText(ReadBytes(file), file.string());
  if (!m.is_object()) fail("expected a JSON object");
  if (!m.contains("zarr_format") || m["zarr_format"] != 2) fail("zarr_format: expected 2");
  if (!m.contains("dtype") || m["dtype"] != dtype)
    fail(std::string("dtype: expected \"") + dtype + "\"");
  if (!m.contains("order") || m["order"] != "C") fail("order: expected \"C\"");
  if (m.contains("filters") && !m["filters"].is_null()) fail("filters: expected null");
  if (m.contains("dimension_separator") && m["dimension_separator"] != ".")
    fail("dimension_separator: expected \".\"");
  ArrayMeta meta;
  meta.shape = Dimensions(m, "shape", rank, file);
  meta.chunks = Dimensions(m, "chunks", rank, file);
  for (std::size_t c : meta.chunks)
    if (c == 0) fail("chunks: expected positive sizes");
  if (m.contains("compressor") && !m["compressor"].is_null()) {
    const json& c = m["compressor"];
    if (!c.is_object() || !c.contains("id") || c["id"] != "zlib")
      fail("compressor: expected {\"id\": \"zlib\"} or null");
    meta.compressor = "zlib";
  }
  if (m.contains("fill_value") && m["fill_value"].is_number())
    meta.fill_value = m["fill_value"].get<double>();
  // The fill value becomes an element of dtype: a float's range, else the conversion is undefined.
  if (std::string(dtype) == "<f4" && std::isfinite(meta.fill_value) &&
      std::abs(meta.fill_value) > std::numeric_limits<float>::max())
    fail("fill_value: expected a number within float32's range");
  return meta;
}

// The chunk's `bytes` decoded; the fill value's when its file is missing (zarr's rule).
template <typename T>
std::vector<T> ReadChunk(const fs::path& file, const std::string& compressor, std::size_t count,
                         double fill_value) {
  // count comes from the store's own .zarray (chunk shape): held to the memory budget before
  // it is allocated, as every reader's sizes are.
  CheckAllocation(SaturatingProduct(count, sizeof(T)), file.string(), "chunk");
  std::vector<T> values(count, static_cast<T>(fill_value));
  if (!fs::exists(file)) return values;
  const std::string data = ReadBytes(file);
  uLongf size = count * sizeof(T);
  if (compressor == "zlib") {
    if (uncompress(reinterpret_cast<Bytef*>(values.data()), &size,
                   reinterpret_cast<const Bytef*>(data.data()), data.size()) != Z_OK ||
        size != count * sizeof(T))
      throw InputError(file.string(), 0, "corrupt zlib chunk or wrong size");
  } else {
    if (data.size() != size) throw InputError(file.string(), 0, "chunk of the wrong size");
    std::memcpy(values.data(), data.data(), size);
  }
  return values;
}

template <typename T>
std::vector<T> Read1d(const fs::path& array, const char* dtype) {
  const ArrayMeta m = ReadMeta(array, dtype, 1);
  CheckAllocation(SaturatingProduct(m.shape[0], sizeof(T)), (array / ".zarray").string(), "shape");
  std::vector<T> values;
  for (std::size_t c = 0; c * m.chunks[0] < m.shape[0]; ++c) {
    std::vector<T> chunk =
        ReadChunk<T>(array / std::to_string(c), m.compressor, m.chunks[0], m.fill_value);
    chunk.resize(std::min(m.chunks[0], m.shape[0] - c * m.chunks[0]));
    values.insert(values.end(), chunk.begin(), chunk.end());
  }
  return values;
}

// A .zattrs file's JSON, or an empty object when the file is missing (attributes are optional).
json ReadAttributes(const fs::path& file) {
  if (!fs::exists(file)) return json::object();
  json a = ParseJsonText(ReadBytes(file), file.string());
  if (!a.is_object()) throw InputError(file.string(), 0, "expected a JSON object");
  return a;
}

// The factor from body/positions' "units" attribute to micrometres: the contract's unit when it
// says none, any length unit a WCON reader knows converted, InputError on anything else.
double PositionsToMicrometres(const fs::path& positions) {
  const fs::path file = positions / ".zattrs";
  const json a = ReadAttributes(file);
  if (!a.contains("units")) return 1;
  const std::string unit = a["units"].is_string() ? a["units"].get<std::string>() : "";
  const double to_mm = WconLengthFactor(unit);
  if (to_mm == 0)
    throw InputError(
        file.string(), 0,
        "units: expected a length unit (micrometre, um, mm, m ...), got " + a["units"].dump());
  return to_mm * 1e3;
}

// The root's "@owval".simulation_scale_m (metres per configuration unit the positions were
// converted with), 0 when the store does not say. InputError when it is not a positive number.
double RecordedSimulationScale_m(const fs::path& store) {
  const fs::path file = store / ".zattrs";
  const json a = ReadAttributes(file);
  if (!a.contains("@owval") || !a["@owval"].is_object() ||
      !a["@owval"].contains("simulation_scale_m"))
    return 0;
  const json& scale = a["@owval"]["simulation_scale_m"];
  if (!scale.is_number() || !(scale.get<double>() > 0) || !std::isfinite(scale.get<double>()))
    throw InputError(
        file.string(), 0,
        "@owval.simulation_scale_m: expected metres per configuration unit, got " + scale.dump());
  return scale.get<double>();
}

}  // namespace

OmeZarrReader::OmeZarrReader(const fs::path& store)
    : path_(store),
      positions_(store / "body/positions"),
      to_micrometres_(PositionsToMicrometres(positions_)),
      simulation_scale_m_(RecordedSimulationScale_m(store)) {
  time_s_ = Read1d<double>(store / "body/time", "<f8");
  type_ = Read1d<float>(store / "body/types", "<f4");
  const ArrayMeta m = ReadMeta(positions_, "<f4", 3);
  const std::string where = (positions_ / ".zarray").string();
  if (m.shape[0] != time_s_.size() || m.shape[1] != type_.size() || m.shape[2] != 3)
    throw InputError(where, 0,
                     "shape: expected (" + std::to_string(time_s_.size()) + ", " +
                         std::to_string(type_.size()) + ", 3), body/time's and body/types' sizes");
  if (m.chunks[1] != m.shape[1] || m.chunks[2] != 3)
    throw InputError(where, 0, "chunks: expected every particle in one chunk of frames");
  chunk_frames_ = m.chunks[0];
  compressor_ = m.compressor;
  fill_value_ = static_cast<float>(m.fill_value);
}

const float* OmeZarrReader::FrameMicrometres(std::size_t frame) {
  const std::size_t chunk = frame / chunk_frames_, n = particle_count() * 3;
  if (chunk != loaded_chunk_) {
    chunk_ = ReadChunk<float>(positions_ / (std::to_string(chunk) + ".0.0"), compressor_,
                              SaturatingProduct(chunk_frames_, n), fill_value_);
    if (to_micrometres_ != 1)  // a store in another length unit, converted once per chunk
      for (float& v : chunk_) v = static_cast<float>(v * to_micrometres_);
    loaded_chunk_ = chunk;
  }
  return chunk_.data() + (frame % chunk_frames_) * n;
}

}  // namespace owval
