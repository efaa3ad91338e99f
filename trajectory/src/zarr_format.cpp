// OME-Zarr viewer contract in zarr v2 layout (zarr-specs v2: .zgroup, .zarray, .zattrs JSON and
// one file per chunk named "i.j.k", C order, little-endian, numcodecs "zlib" compression).
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <set>

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

bool IsChunkName(const std::string& name) {
  return !name.empty() && name.find_first_not_of("0123456789.") == std::string::npos;
}

// Whether `dir` holds only the named files and directories (and chunk files when `chunks`).
bool HoldsOnly(const fs::path& dir, const std::set<std::string>& files,
               const std::set<std::string>& dirs, bool chunks) {
  std::error_code ec;
  fs::directory_iterator it(dir, ec);
  if (ec) return false;
  for (const fs::directory_entry& e : it) {
    const std::string name = e.path().filename().string();
    const fs::file_status status = e.symlink_status(ec);
    if (fs::is_directory(status)      ? !dirs.count(name)
        : fs::is_regular_file(status) ? !files.count(name) && !(chunks && IsChunkName(name))
                                      : true)
      return false;
  }
  return true;
}

void WriteStore(const Trajectory& t, const fs::path& tmp, const ZarrWriteOptions& o) {
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
  WriteText(tmp / "body/.zattrs", json{{"description",
                                        "positions (T, N, 3) in micrometres; types (N,) Sibernetic "
                                        "type codes (1.x liquid, 2.x elastic, 3.x boundary); time "
                                        "(T,) in seconds"}}
                                      .dump(1));
  WritePositions(t, tmp / "body/positions", o);
  Write1d(tmp / "body/types", t.type, "<f4", o.compression_level, json::object());
  Write1d(tmp / "body/time", t.time_s, "<f8", o.compression_level, json{{"units", "s"}});
}

}  // namespace

bool IsOwvalZarrStore(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(path, ec))) return false;
  if (!fs::is_regular_file(fs::symlink_status(path / ".zattrs", ec))) return false;
  try {
    std::ifstream in(path / ".zattrs", std::ios::binary);
    const json attributes = json::parse(in);
    if (!attributes.is_object() || !attributes.contains("@owval")) return false;
  } catch (const json::exception&) {
    return false;
  }
  if (!HoldsOnly(path, {".zgroup", ".zattrs"}, {"body"}, false)) return false;
  if (!HoldsOnly(path / "body", {".zgroup", ".zattrs"}, {"positions", "types", "time"}, false))
    return false;
  for (const char* array : {"positions", "types", "time"})
    if (fs::exists(path / "body" / array) &&
        !HoldsOnly(path / "body" / array, {".zarray", ".zattrs"}, {}, true))
      return false;
  return true;
}

void CheckZarrOutput(const fs::path& path) {
  CheckOutputDirectory(path);  // the parent is writable; a file named PATH is refused
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_empty(path, ec) && !IsOwvalZarrStore(path))
    throw InputError(path.string(), 0,
                     "is a directory but not an OME-Zarr store owval wrote; refusing to replace "
                     "it (name a new or empty directory)");
}

void WriteOmeZarr(const Trajectory& t, const fs::path& path, const ZarrWriteOptions& o) {
  t.CheckShape();
  CheckZarrOutput(path);
  AtomicDirectory store(path, IsOwvalZarrStore);
  WriteStore(t, store.temporary_path(), o);
  store.Commit();
}

}  // namespace owval
