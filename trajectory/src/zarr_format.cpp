// OME-Zarr viewer contract in zarr v2 layout (zarr-specs v2: .zgroup, .zarray, .zattrs JSON and
// one file per chunk named "i.j.k", C order, little-endian, numcodecs "zlib" compression).
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <map>
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

// `path` once CheckZarrOutput accepts it: checked before the temporary store is made.
fs::path Checked(const fs::path& path) {
  CheckZarrOutput(path);
  return path;
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

struct OmeZarrWriter::Store {
  Store(const fs::path& path, const Trajectory& header, const ZarrWriteOptions& o)
      : directory(Checked(path), IsOwvalZarrStore),
        options(o),
        particles(header.particle_count()),
        chunk_frames(std::max<std::size_t>(1, o.frames_per_chunk)),
        to_um(static_cast<float>(o.simulation_scale_m * 1e6)),
        type(header.type),
        time_step_s(header.time_step_s),
        log_step(header.log_step),
        provenance(header.provenance) {
    fs::create_directories(positions_dir());
  }
  fs::path root() const { return directory.temporary_path(); }
  fs::path positions_dir() const { return root() / "body/positions"; }

  AtomicDirectory directory;
  ZarrWriteOptions options;
  std::size_t particles, chunk_frames;
  float to_um;
  std::vector<float> type;
  double time_step_s;
  int log_step;
  std::map<std::string, std::string> provenance;
  std::vector<double> time_s;  // one number a frame: body/time, written at Commit
  std::vector<float> chunk;    // the frames of the chunk being filled, in micrometres
  std::size_t chunks_written = 0;
};

OmeZarrWriter::OmeZarrWriter(const fs::path& path, const Trajectory& header,
                             const ZarrWriteOptions& options)
    : store_(std::make_unique<Store>(path, header, options)) {}

OmeZarrWriter::~OmeZarrWriter() = default;

void OmeZarrWriter::AppendFrame(double time_s, const float* positions) {
  Store& s = *store_;
  s.time_s.push_back(time_s);
  for (std::size_t i = 0; i < s.particles * 3; ++i) s.chunk.push_back(positions[i] * s.to_um);
  if (s.chunk.size() == s.chunk_frames * s.particles * 3) WriteChunk();
}

// A partial last chunk is still stored whole (zarr v2), padded with the fill value.
void OmeZarrWriter::WriteChunk() {
  Store& s = *store_;
  s.chunk.resize(s.chunk_frames * s.particles * 3, 0.f);
  std::string raw(s.chunk.size() * sizeof(float), '\0');
  std::memcpy(raw.data(), s.chunk.data(), raw.size());
  WriteText(s.positions_dir() / (std::to_string(s.chunks_written++) + ".0.0"),
            Compressed(raw, s.options.compression_level));
  s.chunk.clear();
}

void OmeZarrWriter::Commit() {
  Store& s = *store_;
  if (!s.chunk.empty()) WriteChunk();
  const std::size_t frames = s.time_s.size(), n = s.particles;
  const int level = s.options.compression_level;
  const fs::path root = s.root();
  WriteText(root / ".zgroup", json{{"zarr_format", 2}}.dump());
  WriteText(root / ".zattrs", json{{"@owval",
                                    {{"producer", "owval"},
                                     {"provenance", json(s.provenance)},
                                     {"time_step_s", s.time_step_s},
                                     {"log_step", s.log_step},
                                     {"simulation_scale_m", s.options.simulation_scale_m},
                                     {"frames", frames},
                                     {"particles", n}}}}
                                  .dump(1));
  WriteText(root / "body/.zgroup", json{{"zarr_format", 2}}.dump());
  WriteText(root / "body/.zattrs", json{{"description",
                                         "positions (T, N, 3) in micrometres; types (N,) "
                                         "Sibernetic type codes (1.x liquid, 2.x elastic, 3.x "
                                         "boundary); time (T,) in seconds"}}
                                       .dump(1));
  WriteText(s.positions_dir() / ".zarray",
            ArrayMeta({frames, n, 3}, {s.chunk_frames, n, 3}, "<f4", level).dump(1));
  WriteText(s.positions_dir() / ".zattrs",
            json{{"units", "micrometre"}, {"axes", {"time", "particle", "xyz"}}}.dump(1));
  Write1d(root / "body/types", s.type, "<f4", level, json::object());
  Write1d(root / "body/time", s.time_s, "<f8", level, json{{"units", "s"}});
  s.directory.Commit();
}

void WriteOmeZarr(const Trajectory& t, const fs::path& path, const ZarrWriteOptions& o) {
  t.CheckShape();
  OmeZarrWriter writer(path, t, o);
  for (std::size_t f = 0; f < t.frame_count(); ++f)
    writer.AppendFrame(t.time_s[f], t.position(f, 0));
  writer.Commit();
}

}  // namespace owval
