// Streaming HDF5 output and frame-by-frame input (writer.hpp): the datasets of owval's layout
// with an unlimited frame axis, extended one chunk of frames at a time.
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "hdf5_chunk_writer.hpp"
#include "hdf5_chunks.hpp"
#include "hdf5_handle.hpp"
#include "hdf5_preflight.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/trajectory/writer.hpp"
#include "writers.hpp"

namespace owval::internal {
namespace {

// Copies the first `bytes` of `from` to `to`; false (and no `to`) when it cannot.
bool CopyPrefix(const std::filesystem::path& from, const std::filesystem::path& to,
                std::uint64_t bytes) {
  std::error_code error;
  std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing, error);
  if (!error && std::filesystem::file_size(to, error) < bytes && !error)
    error = std::make_error_code(std::errc::io_error);
  if (!error) std::filesystem::resize_file(to, bytes, error);
  if (!error) return true;
  std::filesystem::remove(to, error);
  return false;
}

// One extendible dataset [frames, particles(, components)] and its buffered frames.
struct Stream {
  hid_t set = -1;
  std::size_t values_per_frame = 0;  // particles * components
  std::vector<float> buffer;
};

class Hdf5Writer : public TrajectoryWriter {
 public:
  Hdf5Writer(const std::filesystem::path& destination, const TrajectoryHeader& header,
             const Hdf5WriteOptions& options)
      : out_(destination),
        name_(destination.string()),
        particles_(header.type.size()),
        frames_per_chunk_(std::max<std::size_t>(1, options.frames_per_chunk)),
        chunks_(frames_per_chunk_, std::max<std::size_t>(1, options.particles_per_chunk),
                options.compression_level, options.threads) {
    const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    PrepareHdf5();
    Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
    H5Pset_obj_track_times(fcpl, false);
    file_ = H5Fcreate(out_.temporary_path().c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    if (file_ < 0) throw InputError(name_, 0, "cannot create HDF5 file");
    positions_ = Create("positions", 3, options);
    if (header.velocities) velocities_ = Create("velocities", 3, options);
    if (header.density) density_ = Create("density", 1, options);
    if (header.pressure) pressure_ = Create("pressure", 1, options);
    time_ = CreateTime();
    WriteStatic(header);
  }

  // Continues `file` (a checkpointed run's): datasets shrunk to the checkpoint's whole chunks,
  // the partial mark removed, the pending frames buffered again. A stop checkpoint's (no pending
  // frames) is the file its last periodic checkpoint left: ResumeHdf5Writer appends the frames
  // since.
  Hdf5Writer(const std::filesystem::path& destination, const TrajectoryHeader& header,
             const Hdf5WriteOptions& options, const WriterCheckpoint& checkpoint,
             const std::filesystem::path& file)
      : out_(destination),
        name_(file.string()),
        particles_(header.type.size()),
        frames_per_chunk_(std::max<std::size_t>(1, options.frames_per_chunk)),
        chunks_(frames_per_chunk_, std::max<std::size_t>(1, options.particles_per_chunk),
                options.compression_level, options.threads) {
    const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    PrepareHdf5();
    out_.Adopt(file);
    // The file as a checkpoint left it (not a partial one): Abort() can keep it again.
    if (file.filename() == checkpoint.file) {
      checkpoint_bytes_ = checkpoint.bytes;
      checkpoint_file_frames_ = checkpoint.file_frames;
      superseded_ = PartialPath(destination);  // what Abort() left besides it, if anything
    }
    positions_.values_per_frame = particles_ * 3;
    if (header.velocities) velocities_.values_per_frame = particles_ * 3;
    if (header.density) density_.values_per_frame = particles_;
    if (header.pressure) pressure_.values_per_frame = particles_;
    OpenExisting();
    written_ = checkpoint.file_frames;
    for (Stream* s : Streams()) Shrink(s->set);
    Shrink(time_);
    if (H5Aexists(file_, "partial") > 0 && H5Adelete(file_, "partial") < 0)
      Fail("remove the partial mark");
    if (checkpoint.pending.empty()) return;  // a stop checkpoint's
    Unpack(checkpoint.pending);
    if (written_ + times_.size() != checkpoint.frames)
      throw InputError(name_, 0, "cannot resume: the checkpoint's frame counts disagree");
  }

  ~Hdf5Writer() override {
    const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    try {
      CloseHandles();
    } catch (const InputError&) {
      // Unwinding from a failed write (a full disk): the file is being abandoned anyway, and a
      // destructor must not throw (std::terminate).
    }
  }  // out_ then removes the temporary if not renamed

  void AppendFrame(double time_s, const float* positions, const float* velocities,
                   const float* density, const float* pressure) override {
    Buffer(positions_, positions);
    if (velocities_.set >= 0) Buffer(velocities_, velocities);
    if (density_.set >= 0) Buffer(density_, density);
    if (pressure_.set >= 0) Buffer(pressure_, pressure);
    times_.push_back(time_s);
    if (times_.size() == frames_per_chunk_) {
      const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
      Flush();
    }
  }

  void Close() override {
    const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    Flush();
    Finish();
    out_.Commit();
    RemoveSuperseded();
  }

  void FinishInto(OutputGroup* group) override {
    const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    Flush();
    Finish();
    group->Adopt(&out_);
    RemoveSuperseded();
  }

  // The file is finished in place as the partial one. When a checkpoint was taken, its file is
  // first copied as it stands on disk up to the checkpoint's length (later metadata is still in
  // memory, later chunks lie past that length): the checkpoint's state under the checkpoint's
  // name, which --resume continues as after a SIGKILL, so the result equals an uninterrupted
  // run's byte for byte (finishing the file in place moves its metadata: datasets equal, bytes
  // not). Costs one copy of the file; without room for it, --resume says what is missing.
  void Abort() override {
    const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    const std::filesystem::path checkpointed = out_.temporary_path();
    std::filesystem::path kept = checkpointed;
    kept += ".checkpoint";
    const bool keep = checkpoint_bytes_ > 0 && CopyPrefix(checkpointed, kept, checkpoint_bytes_);
    Flush();
    const int one = 1;
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Handle attr(H5Acreate2(file_, "partial", H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT),
                H5Aclose);
    if (!attr.valid() || H5Awrite(attr, H5T_NATIVE_INT, &one) < 0) Fail("write attribute partial");
    Finish();
    out_.CommitAs(PartialPath(out_.destination()));
    std::error_code ignored;
    if (keep) std::filesystem::rename(kept, checkpointed, ignored);
  }

  std::size_t frames_written() const override { return written_ + times_.size(); }

  // Removes `partial` once the output is complete (Close, FinishInto).
  void Supersede(const std::filesystem::path& partial) { superseded_ = partial; }

  WriterCheckpoint Checkpoint() override {
    const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    WriterCheckpoint c;
    c.file = out_.temporary_path().filename().string();
    c.frames = frames_written();
    c.file_frames = written_;
    c.pending = Pack();
    CloseHandles();
    c.bytes = checkpoint_bytes_ = std::filesystem::file_size(out_.temporary_path());
    checkpoint_file_frames_ = written_;
    OpenExisting();
    out_.KeepOnFailure();
    return c;
  }

  // The file is left as the last Checkpoint() left it (a checkpoint now would close and reopen
  // it where an uninterrupted run does not, and lay it out differently); no pending frames: those
  // since file_frames are read back from the partial file Abort() writes (ResumeHdf5Writer).
  // Without an earlier checkpoint (bytes 0), --resume writes a new file.
  WriterCheckpoint StopCheckpoint() override {
    WriterCheckpoint c;
    c.file = out_.temporary_path().filename().string();
    c.frames = frames_written();
    c.file_frames = checkpoint_file_frames_;
    c.bytes = checkpoint_bytes_;
    return c;
  }

 private:
  // A resumed file is complete: the partial one an interruption left beside it goes.
  void RemoveSuperseded() {
    std::error_code ignored;
    if (!superseded_.empty()) std::filesystem::remove(superseded_, ignored);
  }

  std::vector<Stream*> Streams() {
    std::vector<Stream*> all;
    for (Stream* s : {&positions_, &velocities_, &density_, &pressure_})
      if (s->values_per_frame > 0) all.push_back(s);
    return all;
  }

  // Opens the temporary for appending with metadata evictions off: HDF5 then writes metadata
  // only when flushed (the next checkpoint or the end), so a process killed in between leaves
  // the file as the last checkpoint described it, plus unreferenced chunks past its end.
  void OpenExisting() {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    H5AC_cache_config_t cache;
    cache.version = H5AC__CURR_CACHE_CONFIG_VERSION;
    if (H5Pget_mdc_config(fapl, &cache) < 0) Fail("read the metadata cache configuration");
    cache.evictions_enabled = false;
    cache.incr_mode = H5C_incr__off;
    cache.flash_incr_mode = H5C_flash_incr__off;
    cache.decr_mode = H5C_decr__off;
    if (H5Pset_mdc_config(fapl, &cache) < 0) Fail("configure the metadata cache");
    file_ = H5Fopen(out_.temporary_path().c_str(), H5F_ACC_RDWR, fapl);
    if (file_ < 0) Fail("reopen the file");
    const char* names[] = {"positions", "velocities", "density", "pressure"};
    Stream* streams[] = {&positions_, &velocities_, &density_, &pressure_};
    for (int i = 0; i < 4; ++i) {
      if (streams[i]->values_per_frame == 0) continue;
      streams[i]->set = H5Dopen2(file_, names[i], H5P_DEFAULT);
      if (streams[i]->set < 0) Fail(std::string("open dataset ") + names[i]);
      streams[i]->buffer.reserve(frames_per_chunk_ * streams[i]->values_per_frame);
    }
    time_ = H5Dopen2(file_, "time", H5P_DEFAULT);
    if (time_ < 0) Fail("open dataset time");
  }

  void Shrink(hid_t set) {
    Handle space(H5Dget_space(set), H5Sclose);
    std::vector<hsize_t> dims(std::size_t(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    if (dims.empty() || dims[0] < written_)
      throw InputError(name_, 0,
                       "cannot resume: holds " + std::to_string(dims.empty() ? 0 : dims[0]) +
                           " frames, the checkpoint " + std::to_string(written_));
    dims[0] = written_;
    if (H5Dset_extent(set, dims.data()) < 0) Fail("shrink a dataset to the checkpoint");
  }

  // Buffered frames as bytes: count, times, then each stream's values.
  std::string Pack() {
    std::string out;
    const std::uint64_t n = times_.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    out.append(reinterpret_cast<const char*>(times_.data()), n * sizeof(double));
    for (Stream* s : Streams())
      out.append(reinterpret_cast<const char*>(s->buffer.data()), s->buffer.size() * sizeof(float));
    return out;
  }

  void Unpack(const std::string& in) {
    std::uint64_t n = 0;
    std::size_t expected = sizeof n;
    if (in.size() >= sizeof n) std::memcpy(&n, in.data(), sizeof n);
    if (n >= frames_per_chunk_) throw InputError(name_, 0, "cannot resume: bad pending frames");
    expected += n * sizeof(double);
    for (Stream* s : Streams()) expected += n * s->values_per_frame * sizeof(float);
    if (in.size() != expected) throw InputError(name_, 0, "cannot resume: bad pending frames");
    const char* p = in.data() + sizeof n;
    times_.assign(reinterpret_cast<const double*>(p), reinterpret_cast<const double*>(p) + n);
    p += n * sizeof(double);
    for (Stream* s : Streams()) {
      const std::size_t values = n * s->values_per_frame;
      s->buffer.resize(values);
      std::memcpy(s->buffer.data(), p, values * sizeof(float));
      p += values * sizeof(float);
    }
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(name_, 0, "HDF5: cannot " + what + " (disk full?)");
  }

  Stream Create(const char* dataset, int components, const Hdf5WriteOptions& o) {
    Stream s;
    s.values_per_frame = particles_ * std::size_t(components);
    std::vector<hsize_t> dims = {0, particles_}, max = {H5S_UNLIMITED, particles_},
                         chunk = {frames_per_chunk_,
                                  std::min<hsize_t>(o.particles_per_chunk, particles_)};
    if (components > 1) {
      dims.push_back(hsize_t(components)), max.push_back(hsize_t(components));
      chunk.push_back(hsize_t(components));
    }
    Handle space(H5Screate_simple(int(dims.size()), dims.data(), max.data()), H5Sclose);
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    H5Pset_obj_track_times(dcpl, false);
    H5Pset_chunk(dcpl, int(chunk.size()), chunk.data());
    H5Pset_shuffle(dcpl);
    H5Pset_deflate(dcpl, unsigned(o.compression_level));
    s.set = H5Dcreate2(file_, dataset, H5T_NATIVE_FLOAT, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    if (s.set < 0) Fail(std::string("create dataset ") + dataset);
    s.buffer.reserve(frames_per_chunk_ * s.values_per_frame);
    return s;
  }

  hid_t CreateTime() {
    const hsize_t dims = 0, max = H5S_UNLIMITED, chunk = 1024;
    Handle space(H5Screate_simple(1, &dims, &max), H5Sclose);
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    H5Pset_obj_track_times(dcpl, false);
    H5Pset_chunk(dcpl, 1, &chunk);
    const hid_t set =
        H5Dcreate2(file_, "time", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    if (set < 0) Fail("create dataset time");
    return set;
  }

  void WriteStatic(const TrajectoryHeader& h) {
    const hsize_t n = particles_, six = 6;
    {
      Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
      Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
      H5Pset_obj_track_times(dcpl, false);
      Handle set(H5Dcreate2(file_, "type", H5T_NATIVE_FLOAT, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                 H5Dclose);
      if (!set.valid() ||
          H5Dwrite(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, h.type.data()) < 0)
        Fail("write dataset type");
    }
    const float box[6] = {h.box.xmin, h.box.xmax, h.box.ymin, h.box.ymax, h.box.zmin, h.box.zmax};
    Attribute("box", H5T_NATIVE_FLOAT, box, &six);
    Attribute("time_step_s", H5T_NATIVE_DOUBLE, &h.time_step_s, nullptr);
    Attribute("log_step", H5T_NATIVE_INT, &h.log_step, nullptr);
    for (const auto& [key, value] : h.provenance) {
      Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(type, value.size() + 1);
      Handle space(H5Screate(H5S_SCALAR), H5Sclose);
      const std::string attr_name = "provenance:" + key;
      Handle attr(H5Acreate2(file_, attr_name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
                  H5Aclose);
      if (!attr.valid() || H5Awrite(attr, type, value.c_str()) < 0) Fail("write " + attr_name);
    }
  }

  void Attribute(const char* name, hid_t type, const void* value, const hsize_t* n) {
    Handle space(n ? H5Screate_simple(1, n, nullptr) : H5Screate(H5S_SCALAR), H5Sclose);
    Handle attr(H5Acreate2(file_, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!attr.valid() || H5Awrite(attr, type, value) < 0)
      Fail(std::string("write attribute ") + name);
  }

  void Buffer(Stream& s, const float* values) {
    if (!values) throw std::logic_error("TrajectoryWriter: a field the header declares is missing");
    s.buffer.insert(s.buffer.end(), values, values + s.values_per_frame);
  }

  // Extends `set` to hold `frames` more frames; its new dimensions.
  std::vector<hsize_t> Grow(hid_t set, std::size_t frames) {
    Handle space(H5Dget_space(set), H5Sclose);
    std::vector<hsize_t> dims(std::size_t(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    dims[0] = written_ + frames;
    if (H5Dset_extent(set, dims.data()) < 0) Fail("extend a dataset");
    return dims;
  }

  // Extends `set` by `new_frames` frames and writes the buffered ones at its end through HDF5.
  void Extend(hid_t set, std::size_t new_frames, const void* data, hid_t mem_type) {
    std::vector<hsize_t> count = Grow(set, new_frames), start(count.size(), 0);
    start[0] = written_, count[0] = new_frames;
    Handle file_space(H5Dget_space(set), H5Sclose);
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
    Handle memory(H5Screate_simple(int(count.size()), count.data(), nullptr), H5Sclose);
    if (H5Dwrite(set, mem_type, memory, file_space, H5P_DEFAULT, data) < 0) Fail("write frames");
  }

  // The buffered frames: the float datasets' chunks deflated on all cores (hdf5_chunk_writer),
  // the times through HDF5. Frames are buffered a whole chunk at a time, so written_ is always at
  // a chunk's start.
  void Flush() {
    const std::size_t frames = times_.size();
    if (frames == 0) return;
    std::vector<FloatFrames> sets;
    for (Stream* s : Streams()) {
      Grow(s->set, frames);
      sets.push_back({s->set, s->buffer.data(), particles_, s->values_per_frame / particles_});
    }
    if (!chunks_.Write(sets, written_, frames)) Fail("write frames");
    for (Stream* s : Streams()) s->buffer.clear();
    Extend(time_, frames, times_.data(), H5T_NATIVE_DOUBLE);
    written_ += frames;
    times_.clear();
  }

  void Finish() {
    if (H5Fflush(file_, H5F_SCOPE_LOCAL) < 0) Fail("flush");
    CloseHandles();
  }

  void CloseHandles() {
    for (Stream* s : {&positions_, &velocities_, &density_, &pressure_})
      if (s->set >= 0) H5Dclose(s->set), s->set = -1;
    if (time_ >= 0) H5Dclose(time_), time_ = -1;
    if (file_ >= 0 && H5Fclose(file_) < 0) {
      file_ = -1;
      Fail("close the file");
    }
    file_ = -1;
  }

  AtomicOutput out_;
  std::string name_;
  hsize_t particles_;
  std::size_t frames_per_chunk_, written_ = 0;
  DeflatedChunkWriter chunks_;
  hid_t file_ = -1, time_ = -1;
  Stream positions_, velocities_, density_, pressure_;
  std::vector<double> times_;
  // The file's length and frames at the last checkpoint (0: none, or a partial file adopted).
  std::uint64_t checkpoint_bytes_ = 0, checkpoint_file_frames_ = 0;
  std::filesystem::path superseded_;  // a resumed writer's partial file, removed once complete
};

// Appends frames [first, last) of the partial file an interrupted run left to `writer`; with no
// writer, reads and checks them only (CheckHdf5Resumable).
void AppendFramesOf(const std::filesystem::path& partial, std::size_t first, std::size_t last,
                    const TrajectoryHeader& header, TrajectoryWriter* writer) {
  Hdf5FrameReader in(partial);
  const std::string name = partial.string();
  if (in.header().type.size() != header.type.size() || in.frame_count() < last)
    throw InputError(name, 0,
                     "cannot resume: holds " + std::to_string(in.frame_count()) +
                         " frames, the checkpoint " + std::to_string(last));
  const std::size_t n = header.type.size();
  std::vector<float> positions(3 * n), velocities, density, pressure;
  if (header.velocities) velocities.resize(3 * n);
  if (header.density) density.resize(n);
  if (header.pressure) pressure.resize(n);
  for (std::size_t f = first; f < last; ++f) {
    const double time_s = in.ReadFrame(f, positions.data());
    if (header.velocities) in.ReadField("velocities", f, velocities.data());
    if (header.density) in.ReadField("density", f, density.data());
    if (header.pressure) in.ReadField("pressure", f, pressure.data());
    if (writer)
      writer->AppendFrame(
          time_s, positions.data(), velocities.empty() ? nullptr : velocities.data(),
          density.empty() ? nullptr : density.data(), pressure.empty() ? nullptr : pressure.data());
  }
}

// A stop checkpoint's partial file (the frames since the last periodic checkpoint), after
// checking that it and the periodic checkpoint's file (when there was one) are there.
std::filesystem::path StopCheckpointPartial(const std::filesystem::path& destination,
                                            const WriterCheckpoint& checkpoint) {
  const std::filesystem::path partial = PartialPath(destination);
  if (!std::filesystem::is_regular_file(partial))
    throw InputError(partial.string(), 0,
                     "cannot resume: missing (it holds the frames since the last checkpoint)");
  if (checkpoint.bytes == 0) return partial;
  const std::filesystem::path file = destination.parent_path() / checkpoint.file;
  std::error_code error;
  if (checkpoint.file.empty() || checkpoint.file.find('/') != std::string::npos ||
      std::filesystem::file_size(file, error) < checkpoint.bytes || error)
    throw InputError(file.string(), 0,
                     "cannot resume: missing or shorter than the checkpoint's " +
                         std::to_string(checkpoint.bytes) + " bytes");
  return partial;
}

}  // namespace

std::unique_ptr<TrajectoryWriter> OpenHdf5Writer(const std::filesystem::path& destination,
                                                 const TrajectoryHeader& header,
                                                 const Hdf5WriteOptions& options) {
  return std::make_unique<Hdf5Writer>(destination, header, options);
}

void CheckHdf5Resumable(const std::filesystem::path& destination, const TrajectoryHeader& header,
                        const WriterCheckpoint& checkpoint) {
  if (!checkpoint.pending.empty()) {  // the checkpoint's file, as the periodic checkpoint left it
    const std::filesystem::path file = CheckpointedFile(destination, checkpoint);
    const Hdf5FrameReader in(file);
    if (in.header().type.size() != header.type.size() || in.frame_count() < checkpoint.file_frames)
      throw InputError(file.string(), 0,
                       "cannot resume: holds " + std::to_string(in.frame_count()) +
                           " frames, the checkpoint " + std::to_string(checkpoint.file_frames));
    return;
  }
  AppendFramesOf(StopCheckpointPartial(destination, checkpoint), checkpoint.file_frames,
                 checkpoint.frames, header, nullptr);
}

std::unique_ptr<TrajectoryWriter> ResumeHdf5Writer(const std::filesystem::path& destination,
                                                   const TrajectoryHeader& header,
                                                   const Hdf5WriteOptions& options,
                                                   const WriterCheckpoint& checkpoint) {
  if (!checkpoint.pending.empty())  // a periodic checkpoint's (or an older owval's)
    return std::make_unique<Hdf5Writer>(destination, header, options, checkpoint,
                                        CheckpointedFile(destination, checkpoint));
  // A stop checkpoint's (Hdf5Writer::StopCheckpoint): the last periodic checkpoint's file (or a
  // new one), then the frames since, from the partial file.
  const std::filesystem::path partial = StopCheckpointPartial(destination, checkpoint);
  std::unique_ptr<Hdf5Writer> writer =
      checkpoint.bytes == 0
          ? std::make_unique<Hdf5Writer>(destination, header, options)
          : std::make_unique<Hdf5Writer>(destination, header, options, checkpoint,
                                         destination.parent_path() / checkpoint.file);
  AppendFramesOf(partial, checkpoint.file_frames, checkpoint.frames, header, writer.get());
  writer->Supersede(partial);
  return writer;
}

}  // namespace owval::internal

namespace owval::internal {

// Frames per chunk of a chunked dataset, when a block of that many frames (all particles) takes
// at most 64 MiB: reading whole blocks decompresses each chunk once, straight into the block,
// whatever order frames are asked in. 1 otherwise (a frame a hyperslab).
std::size_t BlockFrames(hid_t set, std::size_t frame_bytes) {
  Handle dcpl(H5Dget_create_plist(set), H5Pclose);
  Handle space(H5Dget_space(set), H5Sclose);
  if (!dcpl.valid() || !space.valid() || H5Pget_layout(dcpl) != H5D_CHUNKED) return 1;
  const int rank = H5Sget_simple_extent_ndims(space);  // [frame][particle] or [frame][particle][3]
  if (rank != 2 && rank != 3) return 1;
  hsize_t chunk[3] = {1, 1, 1};
  if (H5Pget_chunk(dcpl, rank, chunk) != rank || chunk[0] < 1) return 1;
  return SaturatingProduct(std::size_t(chunk[0]), frame_bytes) <= (std::size_t{64} << 20)
             ? std::size_t(chunk[0])
             : 1;
}

}  // namespace owval::internal

namespace owval {

struct Hdf5FrameReader::Dataset {
  std::int64_t set = -1;   // hid_t
  std::size_t values = 0;  // floats a frame (all particles)
  int rank = 3;            // [frame][particle][xyz], or [frame][particle]
  std::size_t block_frames = 1, block_first = SIZE_MAX;  // block holds frames from block_first
  std::vector<float> block;
  // owval's own layout (shuffle, deflate): blocks inflated with buffers kept from block to block.
  std::unique_ptr<internal::DeflatedChunkRows> rows;
  ~Dataset() {
    if (set >= 0) H5Dclose(set);
  }
};

Hdf5FrameReader::Hdf5FrameReader(const std::filesystem::path& path) : path_(path.string()) {
  // The same checks as ReadHdf5, every libhdf5 call made first in a child (hdf5_preflight.hpp).
  internal::PrepareHdf5();
  internal::DryRunHdf5Contained(path_);
  const Trajectory meta = internal::ReadHdf5Metadata(path_);
  header_.box = meta.box;
  header_.time_step_s = meta.time_step_s;
  header_.log_step = meta.log_step;
  header_.type = meta.type;
  header_.provenance = meta.provenance;
  time_s_ = meta.time_s;
  frames_ = time_s_.size();
  const std::lock_guard<std::recursive_mutex> lock(internal::Hdf5Mutex());
  // A metadata cache of at most 2 MiB: the chunk index of a long file is read once, in order,
  // and libhdf5's default cache would grow towards 32 MiB with the number of frames.
  internal::Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  H5AC_cache_config_t mdc{};
  mdc.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  if (H5Pget_mdc_config(fapl, &mdc) >= 0) {
    mdc.set_initial_size = true;
    mdc.initial_size = std::size_t{1} << 20;
    mdc.min_size = std::size_t{1} << 20;
    mdc.max_size = std::size_t{2} << 20;
    H5Pset_mdc_config(fapl, &mdc);
  }
  file_ = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, fapl);
  if (file_ < 0) throw InputError(path_, 0, "HDF5: cannot open the file");
  Open("positions", 3);
  // The dry run has checked the fields' shapes; which of them the file holds:
  header_.velocities = H5Lexists(file_, "velocities", H5P_DEFAULT) > 0;
  header_.density = H5Lexists(file_, "density", H5P_DEFAULT) > 0;
  header_.pressure = H5Lexists(file_, "pressure", H5P_DEFAULT) > 0;
}

Hdf5FrameReader::~Hdf5FrameReader() {
  const std::lock_guard<std::recursive_mutex> lock(internal::Hdf5Mutex());
  sets_.clear();
  if (file_ >= 0) H5Fclose(file_);
}

bool Hdf5FrameReader::partial() const { return header_.provenance.count("partial") > 0; }

Hdf5FrameReader::Dataset& Hdf5FrameReader::Open(const std::string& name,
                                                std::size_t values_per_particle) {
  auto& slot = sets_[name];
  if (slot) return *slot;
  auto d = std::make_unique<Dataset>();
  d->values = header_.type.size() * values_per_particle;
  d->rank = values_per_particle == 1 ? 2 : 3;
  d->set = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
  if (d->set < 0) throw InputError(path_, 0, "HDF5: cannot open /" + name);
  d->block_frames = internal::BlockFrames(d->set, d->values * sizeof(float));
  CheckAllocation(
      SaturatingProduct(d->block_frames, d->values * sizeof(float)), path_,
      "/" + name + ", " + std::to_string(d->block_frames) + " frames (one chunk of frames)");
  if (d->block_frames > 1) {  // whole chunks are read into the block: libhdf5 need cache none
    internal::Handle access(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose);
    H5Pset_chunk_cache(access, 0, 0, 1.0);
    H5Dclose(d->set);
    d->set = H5Dopen2(file_, name.c_str(), access);
    if (d->set < 0) throw InputError(path_, 0, "HDF5: cannot open /" + name);
    std::vector<hsize_t> dims{frames_, header_.type.size()};
    if (d->rank == 3) dims.push_back(3);
    d->rows = internal::DeflatedChunkRows::Open(file_, d->set, path_, dims);
    if (d->rows && d->rows->frames_per_row() != d->block_frames) d->rows.reset();
  }
  slot = std::move(d);
  return *slot;
}

namespace {

// Frames [first, first + count) of a per-frame dataset (rank 3: [frame][particle][3], rank 2:
// [frame][particle]) into out.
void ReadFrames(hid_t set, int rank, std::size_t particles, std::size_t first, std::size_t count,
                float* out, const std::string& path) {
  const hsize_t start[3] = {first, 0, 0}, size[3] = {count, particles, 3};
  internal::Handle space(H5Dget_space(set), H5Sclose);
  H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, size, nullptr);
  internal::Handle memory(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (H5Dread(set, H5T_NATIVE_FLOAT, memory, space, H5P_DEFAULT, out) < 0)
    throw InputError(path, 0, "HDF5: cannot read frame " + std::to_string(first) + " (corrupt?)");
}

}  // namespace

void Hdf5FrameReader::Read(Dataset& d, std::size_t frame, float* out) {
  if (frame >= frames_) throw std::out_of_range("Hdf5FrameReader: frame past the end");
  const std::size_t n = header_.type.size();
  if (d.block_frames == 1) return ReadFrames(d.set, d.rank, n, frame, 1, out, path_);
  const std::size_t first = frame / d.block_frames * d.block_frames;
  if (first != d.block_first) {
    d.block.resize(d.block_frames * d.values);
    d.block_first = SIZE_MAX;  // until the read succeeds
    if (d.rows)
      d.rows->Read(first, d.block.data());
    else
      ReadFrames(d.set, d.rank, n, first, std::min(d.block_frames, frames_ - first), d.block.data(),
                 path_);
    d.block_first = first;
  }
  const float* x = d.block.data() + (frame - first) * d.values;
  std::copy(x, x + d.values, out);
}

double Hdf5FrameReader::ReadFrame(std::size_t frame, float* positions) {
  const std::lock_guard<std::recursive_mutex> lock(internal::Hdf5Mutex());
  Dataset& d = *sets_.at("positions");
  Read(d, frame, positions);
  for (std::size_t i = 0; i < d.values; ++i)
    if (!std::isfinite(positions[i]))
      throw NonFiniteTrajectoryError(path_, 0,
                                     internal::NonFinitePositionMessage(frame, i / 3, i % 3));
  return time_s_[frame];
}

void Hdf5FrameReader::ReadField(const std::string& field, std::size_t frame, float* values) {
  const std::lock_guard<std::recursive_mutex> lock(internal::Hdf5Mutex());
  const bool held =
      field == "velocities"
          ? header_.velocities
          : (field == "density" ? header_.density : field == "pressure" && header_.pressure);
  if (!held) throw InputError(path_, 0, "HDF5: no /" + field + " in this file");
  Read(Open(field, field == "velocities" ? 3 : 1), frame, values);
}

}  // namespace owval
