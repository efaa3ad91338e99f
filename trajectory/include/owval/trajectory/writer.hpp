#pragma once
// Streaming trajectory output (issue 16): frames are written as they are produced, so a run's
// memory is O(particles), whatever its length.
//
//   TrajectoryHeader header{box, dt, log_step, types};
//   auto writer = OpenTrajectoryWriter("out/trajectory.h5", header);
//   for (each recorded step) writer->AppendFrame(time_s, positions);   // 3 floats a particle
//   writer->Close();   // complete: renamed onto out/trajectory.h5
//   // or, on SIGINT / SIGTERM / divergence:
//   writer->Abort();   // what was appended so far, readable, as out/trajectory.partial.h5
//
// Formats by extension: .h5/.hdf5 is owval's HDF5 (datasets extended chunk by chunk, frames
// buffered one chunk at a time); anything else is Sibernetic text in the OpenCL or native layout
// (rows appended, buffered 4 MiB at a time), byte for byte what WriteSiberneticText writes.
// Until Close() or Abort(), the data lives under a temporary name beside the destination; a
// writer destroyed without either removes it (an exception unwinding a run leaves nothing).
// A partial trajectory is named PARTIAL = stem + ".partial" + extension; in HDF5 it also carries
// the root attribute `partial` = 1 (ReadHdf5 sets provenance["partial"] = "1"); the text format
// has no metadata, so there the name alone says it.
//
// Integration (engine::Run belongs to the engine): open the writer once the first frame's
// particle types are known, AppendFrame at each logged step instead of Trajectory::AppendFrame,
// Close at the end, Abort from the interrupt path.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "owval/base/atomic_output.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval {

struct TrajectoryHeader {
  Box box;
  double time_step_s = 0;
  int log_step = 1;
  std::vector<float> type;                        // every particle's type code, in file order
  std::map<std::string, std::string> provenance;  // HDF5 only
  bool velocities = false;  // HDF5 only: AppendFrame then takes velocities (3 floats a particle)
  bool density = false;     // HDF5 only: and density (1 float a particle)
  bool pressure = false;    // HDF5 only: and pressure (1 float a particle)
};

// Where a writer's output stood at a checkpoint: what ResumeTrajectoryWriter needs to continue
// it after the process that wrote it stopped (killed, interrupted), with the same result as an
// uninterrupted writer's. Saved by the caller beside its own state (engine/long_run.hpp).
struct WriterCheckpoint {
  std::string file;               // the file being written, name only (beside the destination)
  std::uint64_t frames = 0;       // frames appended before the checkpoint
  std::uint64_t bytes = 0;        // the file's length at the checkpoint
  std::uint64_t file_frames = 0;  // HDF5: frames in the datasets (whole chunks only)
  // HDF5: the frames after those, not yet in the file (binary); empty in a StopCheckpoint's,
  // whose frames after file_frames are in the partial file.
  std::string pending;
};

struct TrajectoryWriterOptions {
  TextLayout layout = TextLayout::kOpenCL;  // text only
  Hdf5WriteOptions hdf5;                    // chunk shape and deflate level
};

class TrajectoryWriter {
 public:
  virtual ~TrajectoryWriter() = default;
  // One frame: positions (3 floats a particle, cu); velocities, density and pressure when the
  // header asks for them. Throws InputError naming the file on an I/O failure (a full disk).
  virtual void AppendFrame(double time_s, const float* positions, const float* velocities = nullptr,
                           const float* density = nullptr, const float* pressure = nullptr) = 0;
  // Writes what is buffered and renames the file onto its destination.
  virtual void Close() = 0;
  // Writes what is buffered and closes the file under its temporary name, which `group` then
  // renames onto the destination together with the command's other outputs.
  virtual void FinishInto(OutputGroup* group) = 0;
  // Writes what is buffered, marks the file partial and renames it onto PartialPath(destination).
  virtual void Abort() = 0;
  virtual std::size_t frames_written() const = 0;
  // Makes the output continuable from this frame after a crash and says how (the checkpoint
  // rule: text flushed, its length recorded; HDF5 closed and reopened with metadata evictions
  // off, so until the next checkpoint the file on disk stays the one described, and only whole
  // chunks in it: later frames are written into new chunks only). Afterwards the temporary
  // outlives an uncommitted writer, for ResumeTrajectoryWriter.
  virtual WriterCheckpoint Checkpoint() = 0;
  // The checkpoint of a run that stops (Abort() follows): ResumeTrajectoryWriter then continues
  // as if the run had not stopped, byte for byte. HDF5 keeps the last Checkpoint()'s file state
  // and reads the frames since back from the partial file (closing and reopening the file here
  // would lay it out unlike an uninterrupted run's).
  virtual WriterCheckpoint StopCheckpoint() { return Checkpoint(); }
};

std::unique_ptr<TrajectoryWriter> OpenTrajectoryWriter(const std::filesystem::path& destination,
                                                       const TrajectoryHeader& header,
                                                       const TrajectoryWriterOptions& options = {});

// Continues the output a checkpoint describes: checkpoint.file beside `destination`, or
// PartialPath(destination) when an interrupted run renamed it, cut back to the checkpoint
// (text truncated, HDF5 datasets shrunk, the `partial` mark removed), its pending frames
// buffered again. After an HDF5 StopCheckpoint: checkpoint.file as the periodic checkpoint
// before it left it (or a new file), then the frames since, read from PartialPath(destination).
// InputError naming the file when neither exists or it is shorter than the checkpoint says.
std::unique_ptr<TrajectoryWriter> ResumeTrajectoryWriter(
    const std::filesystem::path& destination, const TrajectoryHeader& header,
    const WriterCheckpoint& checkpoint, const TrajectoryWriterOptions& options = {});

// Throws the InputError ResumeTrajectoryWriter would, and changes no file: a caller continuing
// several outputs checks every one before it continues any, so that a refused resumption leaves
// each as it was (the text output was cut back to its checkpoint before the HDF5 one was found
// truncated). Reads the HDF5 frames a resumption would copy.
void CheckResumable(const std::filesystem::path& destination, const TrajectoryHeader& header,
                    const WriterCheckpoint& checkpoint);

// out/trajectory.h5 -> out/trajectory.partial.h5; position_buffer.txt ->
// position_buffer.partial.txt
std::filesystem::path PartialPath(const std::filesystem::path& destination);
// Whether `path` is named as PartialPath names a partial trajectory: the text format has no
// metadata, so its name is what says so.
bool IsPartialPath(const std::filesystem::path& path);

// Reads an HDF5 trajectory frame by frame (memory O(particles)): the same checks as ReadHdf5
// (docs/fuzzing.md) at open, then one hyperslab a frame.
class Hdf5FrameReader {
 public:
  explicit Hdf5FrameReader(const std::filesystem::path& path);
  ~Hdf5FrameReader();
  Hdf5FrameReader(const Hdf5FrameReader&) = delete;
  Hdf5FrameReader& operator=(const Hdf5FrameReader&) = delete;

  const TrajectoryHeader& header() const { return header_; }  // velocities etc.: the file's
  std::size_t frame_count() const { return frames_; }
  const std::vector<double>& time_s() const { return time_s_; }  // every frame's time
  bool partial() const;
  // Frame f's time and positions (3 * particles floats). Throws InputError on a corrupt chunk
  // or a non-finite position. Frames are read a chunk of frames at a time (all particles, at
  // most 64 MiB: 3.4 MB for demo1's 16 frames x 17,841 particles), so each chunk is decompressed
  // once, whatever order frames are asked in.
  double ReadFrame(std::size_t frame, float* positions);
  // Frame f's values of a per-frame field the file holds (header(): "velocities", 3 floats a
  // particle; "density" or "pressure", 1), read a chunk of frames at a time as positions are,
  // the field's dataset opened at its first read. Not checked for finiteness (as ReadHdf5: a
  // diverged run's density may be NaN, its positions may not). InputError on a corrupt chunk.
  void ReadField(const std::string& field, std::size_t frame, float* values);

 private:
  struct Dataset;  // one per-frame dataset and its block of frames
  Dataset& Open(const std::string& name, std::size_t values_per_particle);
  void Read(Dataset& set, std::size_t frame, float* out);

  std::string path_;
  std::int64_t file_ = -1;  // HDF5 identifier (hid_t)
  TrajectoryHeader header_;
  std::vector<double> time_s_;
  std::size_t frames_ = 0;
  std::map<std::string, std::unique_ptr<Dataset>> sets_;  // "positions", then fields as read
};

}  // namespace owval
