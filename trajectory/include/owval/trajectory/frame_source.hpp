#pragma once
// Trajectories read frame by frame (issue 16): what compare and render take, so that a
// 25,000-frame file costs O(particles) of memory, not the whole trajectory.
//
//   auto source = OpenFrameSource("run/trajectory.h5");   // or position_buffer.txt(.gz)
//   const Trajectory& header = source->header();           // box, types, every frame's time
//   for (std::size_t f = 0; f < source->frame_count(); ++f) {
//     const FrameRef frame = source->Frame(f);             // valid until the next Frame()
//     Centroid(frame.trajectory, frame.frame, members);     // any (trajectory, frame) function
//   }
//
// A FrameRef is a trajectory and a frame index in it: the whole in-memory trajectory and f for
// MemoryFrameSource (no copy), a one-frame trajectory and 0 for the file sources. Every function
// of owval that reads one frame of a Trajectory therefore reads a streamed frame unchanged, with
// the same floating-point operations in the same order: streamed and whole-trajectory results
// are identical.
//
// Formats: owval HDF5 (Hdf5FrameReader: a chunk of frames at a time, each chunk decompressed
// once) and Sibernetic text in either layout, plain or gzip-compressed (read in
// 1 MiB blocks; the file is scanned once at open, with every check ReadSiberneticText makes, to
// detect the layout and find where each frame starts). Frames may be asked for in any order;
// forward is the cheap direction (a gzip file is decompressed again from its start to go back).
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval {

struct FrameRef {
  const Trajectory& trajectory;
  std::size_t frame;  // index into trajectory
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Box, time step, log step, types, provenance (with "partial" for an interrupted run's output)
  // and every frame's time. Its per-frame arrays are not to be read: use Frame().
  virtual const Trajectory& header() const = 0;
  // Frame f (f < frame_count()); the reference stays valid until the next call. Throws
  // InputError naming the file on a corrupt frame, std::out_of_range past the end.
  virtual FrameRef Frame(std::size_t f) = 0;

  // From now on Frame() gives the frame's velocities, density and pressure too, those the file
  // holds (frame.trajectory.has_density() ...). A file source reads positions only until asked:
  // the fields are most of an HDF5 file. Sibernetic text holds none; a trajectory in memory
  // gives its own.
  virtual void ReadFields() {}

  // Frames [first, first + count) of one per-frame array into `out`, frame after frame:
  // "positions" (3 floats a particle), or a field the source's frames hold ("velocities", 3;
  // "density" or "pressure", 1). What WriteHdf5 copies a dataset at a time. This one goes through
  // Frame(); an HDF5 file reads that one dataset, where Frame() would also read every field asked
  // for (HDF5 to HDF5 with fields read each field three times, positions four).
  virtual void CopyFrames(const std::string& array, std::size_t first, std::size_t count,
                          float* out);

  std::size_t frame_count() const { return header().frame_count(); }
  std::size_t particle_count() const { return header().particle_count(); }
  bool partial() const { return header().provenance.count("partial") > 0; }
};

// InputError naming `file` when `frames` holds fewer than `at_least` frames ("holds 1 frame(s);
// expected at least 2"): what a measurement over time needs, said of the file, not of a window.
void RequireFrames(const FrameSource& frames, const std::filesystem::path& file,
                   std::size_t at_least);

// A trajectory already in memory (no copy: it must outlive the source).
std::unique_ptr<FrameSource> MemoryFrameSource(const Trajectory& trajectory);

// Any trajectory file ReadTrajectory reads, frame by frame. The checks at open are
// ReadTrajectory's (a text file's layout detected unless options.layout says otherwise); report,
// when given, is filled as ReadTrajectory fills it.
std::unique_ptr<FrameSource> OpenFrameSource(const std::filesystem::path& path,
                                             const TextReadOptions& options = {},
                                             TextReadReport* report = nullptr);

// WriteHdf5 of the source's trajectory, frame by frame: the same bytes, with the per-frame fields
// the source holds (positions, then each field, read in one pass a dataset), holding one chunk's
// frames (Hdf5WriteOptions::frames_per_chunk) of one dataset at a time.
void WriteHdf5(FrameSource& frames, const std::filesystem::path& path,
               const Hdf5WriteOptions& options = {});

}  // namespace owval
