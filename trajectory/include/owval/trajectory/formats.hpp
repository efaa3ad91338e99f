#pragma once
// Trajectory files. Three formats:
//  - Sibernetic OpenCL position_buffer.txt: 11 header lines (xmin xmax ymin ymax zmin zmax,
//    elastic, liquid and boundary counts, time step, log step), then rows "x\ty\tz\ttype";
//    frame 0 lists every particle, later frames only the non-boundary ones.
//  - Native (Metal/CUDA) dumps: the same header and rows, boundary particles in every frame.
//  - HDF5 in owval's layout (design notes §3): /positions [frames, particles, 3] float32, /time,
//    /type, optional /velocities, /density, /pressure, provenance as root attributes.
// Readers throw InputError("file:line: what was expected") on any malformed input.
#include <filesystem>
#include <string>
#include <string_view>

#include "owval/trajectory/trajectory.hpp"

namespace owval {

enum class TextLayout {
  kAuto,    // detect from the counts (reading only)
  kOpenCL,  // Sibernetic: boundary particles only in frame 0
  kNative,  // boundary particles in every frame
};
const char* LayoutName(TextLayout layout);
// "auto" | "opencl" | "native"; throws InputError otherwise.
TextLayout ParseLayout(const std::string& name);

struct TextReadOptions {
  TextLayout layout = TextLayout::kAuto;  // force a layout instead of detecting it
  bool quiet = false;                     // no progress line
};

struct TextReadReport {
  TextLayout detected = TextLayout::kAuto;  // the layout actually used
  std::size_t rows = 0;                     // position rows parsed
  std::size_t bytes = 0;
  std::string description;  // e.g. "opencl layout: 2500 frames, 1 moving + 2168 boundary"
};

Trajectory ReadSiberneticText(const std::filesystem::path& path,
                              const TextReadOptions& options = {},
                              TextReadReport* report = nullptr);
// Same, from text already in memory (name is used in error messages).
Trajectory ParseSiberneticText(std::string_view text, const std::string& name,
                               const TextReadOptions& options = {},
                               TextReadReport* report = nullptr);

// Writes with 6 significant digits (Sibernetic's ostream default), atomically.
void WriteSiberneticText(const Trajectory& trajectory, const std::filesystem::path& path,
                         TextLayout layout = TextLayout::kOpenCL);

struct Hdf5WriteOptions {
  int compression_level = 4;               // deflate level 0..9
  std::size_t frames_per_chunk = 16;       // chunking along the frame axis
  std::size_t particles_per_chunk = 1024;  // and along the particle axis
  // Threads deflating chunks in parallel (0: OpenMP's maximum). A run passes its solver's: the
  // pool's idle threads spin after each flush, on cores a one-thread run leaves to others.
  int threads = 0;
};
void WriteHdf5(const Trajectory& trajectory, const std::filesystem::path& path,
               const Hdf5WriteOptions& options = {});
Trajectory ReadHdf5(const std::filesystem::path& path);

enum class FileFormat { kSiberneticText, kHdf5 };
// By content (HDF5 signature) first, then by extension (.h5/.hdf5).
FileFormat DetectFormat(const std::filesystem::path& path);

// Reads any supported trajectory file.
Trajectory ReadTrajectory(const std::filesystem::path& path, const TextReadOptions& options = {},
                          TextReadReport* report = nullptr);
// The trajectory file extensions owval writes: ".h5", ".hdf5" (owval HDF5), ".txt"
// (Sibernetic text), ".wcon" (WCON) and ".zarr" (OME-Zarr, a directory). Checks before any work
// that `path` has one of them and can be written; InputError naming the path otherwise.
void CheckTrajectoryOutput(const std::filesystem::path& path);

// Writes by extension: .h5/.hdf5 -> HDF5, anything else -> Sibernetic text in `layout`.
void WriteTrajectory(const Trajectory& trajectory, const std::filesystem::path& path,
                     TextLayout layout = TextLayout::kOpenCL);

}  // namespace owval
