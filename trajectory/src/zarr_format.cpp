// OME-Zarr viewer contract in zarr v2 layout (zarr-specs v2: .zgroup, .zarray, .zattrs JSON and
// one file per chunk named "i.j.k", C order, little-endian, numcodecs "zlib" compression).
#include <zlib.h>

#include <cstring>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string Compressed(const std::string& raw, int level) {
  if (level <= 0) return raw;
  uLongf size = compressBound(raw.size());
  std::string out(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &size,
                reinterpret_cast<const Bytef*>(raw.data()), raw.size(), level) != Z_OK)
    throw std::runtime_error("zlib compress2 failed");
  out.resize(size);
  return out;
}

json ArrayMeta(const std::vector<std::size_t>& shape, const std::vector<std::size_t>& chunks,
               const char* dtype, int level) {
  json compressor = level > 0 ? json{{"id", "zlib"}, {"level", level}} : json(nullptr);
  return {{"zarr_format", 2}, {"shape", shape},           {"chunks", chunks},
          {"dtype", dtype},   {"compressor", compressor}, {"fill_value", 0},
          {"order", "C"},     {"filters", nullptr},       {"dimension_separator", "."}};
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) throw InputError(path.string(), 0, "cannot write");
}

// A one-dimensional array stored as a single chunk.
template <typename T>
void Write1d(const fs::path& dir, const std::vector<T>& values, const char* dtype, int level,
             const json& attributes) {
  fs::create_directories(dir);
  WriteText(
      dir / ".zarray",
      ArrayMeta({values.size()}, {std::max<std::size_t>(values.size(), 1)}, dtype, level).dump(1));
  WriteText(dir / ".zattrs", attributes.dump(1));
  std::string raw(values.size() * sizeof(T), '\0');
  std::memcpy(raw.data(), values.data(), raw.size());
  WriteText(dir / "0", Compressed(raw, level));
}

void WritePositions(const Trajectory& t, const fs::path& dir, const ZarrWriteOptions& o) {
  const std::size_t n = t.particle_count(), frames = t.frame_count();
  const std::size_t chunk = std::max<std::size_t>(1, o.frames_per_chunk);
  fs::create_directories(dir);
  WriteText(dir / ".zarray",
            ArrayMeta({frames, n, 3}, {chunk, n, 3}, "<f4", o.compression_level).dump(1));
  WriteText(dir / ".zattrs",
            json{{"units", "micrometre"}, {"axes", {"time", "particle", "xyz"}}}.dump(1));
  const float to_um = static_cast<float>(o.simulation_scale_m * 1e6);
  for (std::size_t c = 0; c * chunk < frames; ++c) {
    // A partial last chunk is still stored whole (zarr v2), padded with the fill value.
    std::vector<float> values(chunk * n * 3, 0.f);
    const std::size_t first = c * chunk, last = std::min(frames, first + chunk);
    for (std::size_t i = 0; i < (last - first) * n * 3; ++i)
      values[i] = t.positions[first * n * 3 + i] * to_um;
    std::string raw(values.size() * sizeof(float), '\0');
    std::memcpy(raw.data(), values.data(), raw.size());
    WriteText(dir / (std::to_string(c) + ".0.0"), Compressed(raw, o.compression_level));
  }
}

}  // namespace

void WriteOmeZarr(const Trajectory& t, const fs::path& path, const ZarrWriteOptions& o) {
  t.CheckShape();
  const fs::path tmp = path.parent_path() / (path.filename().string() + ".partial");
  fs::remove_all(tmp);
  try {
    fs::create_directories(tmp / "body");
    json provenance(t.provenance);
    WriteText(tmp / ".zgroup", json{{"zarr_format", 2}}.dump());
    WriteText(tmp / ".zattrs", json{{"@owval",
                                     {{"producer", "owval"},
                                      {"provenance", provenance},
                                      {"time_step_s", t.time_step_s},
                                      {"log_step", t.log_step},
                                      {"simulation_scale_m", o.simulation_scale_m},
                                      {"frames", t.frame_count()},
                                      {"particles", t.particle_count()}}}}
                                   .dump(1));
    WriteText(tmp / "body/.zgroup", json{{"zarr_format", 2}}.dump());
    WriteText(tmp / "body/.zattrs",
              json{{"description",
                    "positions (T, N, 3) in micrometres; types (N,) Sibernetic "
                    "type codes (1.x liquid, 2.x elastic, 3.x boundary); time "
                    "(T,) in seconds"}}
                  .dump(1));
    WritePositions(t, tmp / "body/positions", o);
    Write1d(tmp / "body/types", t.type, "<f4", o.compression_level, json::object());
    Write1d(tmp / "body/time", t.time_s, "<f8", o.compression_level, json{{"units", "s"}});
    fs::remove_all(path);
    fs::rename(tmp, path);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
    throw;
  }
}

}  // namespace owval
