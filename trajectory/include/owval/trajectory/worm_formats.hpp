#pragma once
// The worm's formats for other OpenWorm tools:
//  - WCON (openworm/tracker-commons WCON_format.md): one track, "units" {t: s, x, y, cx, cy: mm},
//    "data" [{id, t[], x[][], y[][], cx[], cy[], head: "L"}] with increasing t and equal-length
//    x/y arrays per time, "metadata.software" {name, version, settings}, owval's own keys under
//    "@owval". The body plane is chosen by the producer (owval: WCON x = simulation z, WCON y =
//    simulation x, see kinematics/midline.hpp).
//  - OME-Zarr viewer contract in zarr v2 layout: body/positions (T, N, 3) float32 in micrometres,
//    chunked by frames, body/types (N,) float32, body/time (T,) float64 seconds, provenance as
//    attributes of the root group. Readable by zarr-python without owval.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/trajectory/trajectory.hpp"

namespace owval {

// What a WCON file holds for one worm.
struct WormTrack {
  std::string id = "1";
  std::vector<double> time_s;                  // increasing
  std::vector<std::vector<float>> x_mm, y_mm;  // per time, head first, equal lengths
  std::vector<double> cx_mm, cy_mm;            // centroid per time (empty: none written)
  std::string software_version;                // owval's version
  nlohmann::json software_settings = nlohmann::json::object();  // configuration hash, backend..
  nlohmann::json owval = nlohmann::json::object();              // the "@owval" block
};

// The file text (x, y with 9 significant digits, t, cx, cy with 17: values read back exactly).
std::string WconText(const WormTrack& track);
// Checks the track (sizes, increasing time, finite values), then writes atomically.
void WriteWcon(const WormTrack& track, const std::filesystem::path& path);
// WriteWcon time point by time point, the same bytes: the text puts every t, cx and cy before the
// first x, so each array is spooled to an anonymous temporary file (gone with the process, even
// killed) and the file is assembled at Commit(). Memory: one time point, never the track. Each
// time point is checked as WriteWcon checks it, when appended.
class WconWriter {
 public:
  // `head`: id, software version and settings, "@owval"; its per-time arrays are not read.
  // `centroid`: whether every time point has cx, cy (the track's cx_mm non-empty).
  WconWriter(std::filesystem::path path, const WormTrack& head, bool centroid);
  ~WconWriter();
  WconWriter(const WconWriter&) = delete;
  WconWriter& operator=(const WconWriter&) = delete;
  // cx_mm, cy_mm are ignored without `centroid`.
  void Append(double time_s, const std::vector<float>& x_mm, const std::vector<float>& y_mm,
              double cx_mm = 0, double cy_mm = 0);
  // Writes the file atomically. InputError when no time point was appended.
  void Commit();

 private:
  std::FILE* Spool(int array);
  std::filesystem::path path_;
  std::string head_;  // the text before the data arrays
  bool centroid_;
  std::size_t points_ = 0;
  double last_time_s_ = 0;
  std::FILE* spools_[5] = {};  // t, cx, cy, x, y: their elements as WconText prints them
};

// One time point of a WCON track: t in s, the skeleton and centroid in mm.
struct WconTimePoint {
  double time_s = 0;
  std::vector<float> x_mm, y_mm;  // head first, equal lengths
  double cx_mm = 0, cy_mm = 0;    // when the track has a centroid (WconReader::has_centroid)
};

// The one WCON reader: the records of the first worm id, in file order, a time point at a time
// (t must increase across them); t converted to s and x, y, cx, cy to mm from the file's units
// (x, y as floats), ox/oy origins applied; unknown keys ignored. Memory: one time point and the
// metadata, never the track. The file is parsed once with nlohmann::json's SAX interface
// (json::sax_parse), keeping the units, metadata.software's version and settings, "@owval" and
// one small entry per record; the first id's per-time arrays (t, cx, cy, ox, oy, x, y) go to
// anonymous temporary files as binary doubles, since a WCON puts every time's x before the first
// y (and a record's keys come in any order), and are read back in step.
// InputError naming the file and field on anything a WCON reader must refuse (a record without
// id, t, x or y; non-numbers; sizes that differ; unknown units; coordinates beyond what the track
// stores); a time that is not finite and increasing is refused by Next(). JSON that does not
// parse is refused as FILE:LINE:COLUMN (the byte where the parser stopped, counted while reading).
class WconReader {
 public:
  explicit WconReader(const std::filesystem::path& path);
  ~WconReader();
  WconReader(const WconReader&) = delete;
  WconReader& operator=(const WconReader&) = delete;
  // The track without time points: id, software version and settings, "@owval".
  const WormTrack& head() const;
  std::size_t size() const;  // time points of the first id
  bool has_centroid() const;
  // The next time point into `point`; false after the last.
  bool Next(WconTimePoint* point);
  // Back to the first time point, without parsing the file again.
  void Rewind();

  struct Parsed;

 private:
  std::unique_ptr<Parsed> parsed_;
};

// The point appended to the track's per-time arrays (cx, cy only when `centroid`): every reader
// that collects time points into a WormTrack (ReadWcon, the midline log's) does it here.
void AppendTimePoint(const WconTimePoint& point, bool centroid, WormTrack* track);

// The whole track: WconReader's head and every time point (memory: the track).
WormTrack ReadWcon(const std::filesystem::path& path);

struct ZarrWriteOptions {
  std::size_t frames_per_chunk = 16;           // chunk along time; one chunk holds every particle
  double simulation_scale_m = 7.39999905e-06;  // metres per configuration unit
  int compression_level = 1;                   // zlib (numcodecs "zlib"), 0 = uncompressed
};
// Writes the directory atomically (a temporary sibling renamed when complete). Replaces only an
// empty directory or an OME-Zarr store owval wrote (IsOwvalZarrStore); InputError otherwise.
void WriteOmeZarr(const Trajectory& trajectory, const std::filesystem::path& path,
                  const ZarrWriteOptions& options = {});

// WriteOmeZarr frame by frame, the same bytes: positions go out a chunk of frames at a time
// (memory: one chunk, frames_per_chunk x particles), the arrays whose shape needs the frame count
// at Commit(). Until then the store is a temporary sibling, removed if the writer is destroyed
// uncommitted. Checks `path` as CheckZarrOutput does, before anything is written.
class OmeZarrWriter {
 public:
  // `header`: types, time step, log step and provenance (its per-frame arrays are not read).
  OmeZarrWriter(const std::filesystem::path& path, const Trajectory& header,
                const ZarrWriteOptions& options = {});
  ~OmeZarrWriter();
  OmeZarrWriter(const OmeZarrWriter&) = delete;
  OmeZarrWriter& operator=(const OmeZarrWriter&) = delete;
  // One frame: 3 floats a particle, configuration units.
  void AppendFrame(double time_s, const float* positions);
  void Commit();

 private:
  struct Store;
  void WriteChunk();
  std::unique_ptr<Store> store_;
};

// An OME-Zarr store read back a chunk of frames at a time (memory: one chunk): zarr v2,
// body/positions (T, N, 3) "<f4" in micrometres chunked along time only, body/time (T,) "<f8" s,
// body/types (N,) "<f4"; C order, compressor zlib or none, no filters. What owval writes, and
// what another writer of the same contract writes. InputError naming the file on anything else
// (a chunk that is missing is the fill value, as zarr reads it). The positions' unit is what
// body/positions/.zattrs "units" says (owval writes "micrometre"; a store in mm or m is converted,
// an unknown unit refused naming the file); none said is the contract's micrometres. Memory: one
// chunk of frames and the store's times and types, never the positions of every frame.
class OmeZarrReader {
 public:
  explicit OmeZarrReader(const std::filesystem::path& store);
  const std::filesystem::path& path() const { return path_; }
  // Metres per configuration unit the store says its positions were converted with (root
  // .zattrs "@owval".simulation_scale_m, as OmeZarrWriter records it); 0 when it does not say.
  double simulation_scale_m() const { return simulation_scale_m_; }
  std::size_t frame_count() const { return time_s_.size(); }
  std::size_t particle_count() const { return type_.size(); }
  const std::vector<double>& time_s() const { return time_s_; }
  const std::vector<float>& type() const { return type_; }
  // Frame `frame`'s positions in micrometres, 3 a particle; valid until the next call.
  const float* FrameMicrometres(std::size_t frame);

 private:
  std::filesystem::path path_, positions_;
  double to_micrometres_ = 1, simulation_scale_m_ = 0;
  std::string compressor_;  // "zlib" or "" (none)
  std::size_t chunk_frames_ = 1, loaded_chunk_ = SIZE_MAX;
  float fill_value_ = 0;
  std::vector<double> time_s_;
  std::vector<float> type_, chunk_;
};

// An OME-Zarr store as WriteOmeZarr writes it: its root .zattrs has owval's "@owval" block and it
// holds nothing but owval's groups, arrays and chunks (so replacing it loses nothing else).
bool IsOwvalZarrStore(const std::filesystem::path& path);
// Checks before any work that WriteOmeZarr may write `path`: its parent is writable and it is
// missing, an empty directory or an owval store. InputError naming the path otherwise.
void CheckZarrOutput(const std::filesystem::path& path);

}  // namespace owval
