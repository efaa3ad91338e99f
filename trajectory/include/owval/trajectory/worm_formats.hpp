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
#include <filesystem>
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
// Reads the records of the first worm id, in file order (t must increase across them); converts t
// to s and x, y, cx, cy to mm from the file's units; applies ox/oy origins. Ignores unknown keys.
// InputError naming the file and field on anything a WCON reader must refuse.
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

// An OME-Zarr store as WriteOmeZarr writes it: its root .zattrs has owval's "@owval" block and it
// holds nothing but owval's groups, arrays and chunks (so replacing it loses nothing else).
bool IsOwvalZarrStore(const std::filesystem::path& path);
// Checks before any work that WriteOmeZarr may write `path`: its parent is writable and it is
// missing, an empty directory or an owval store. InputError naming the path otherwise.
void CheckZarrOutput(const std::filesystem::path& path);

}  // namespace owval
