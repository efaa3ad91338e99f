// owval's HDF5 layout (design notes §3): /positions float32 [frames, particles, 3] chunked along
// frames and deflate-compressed with the shuffle filter, /time float64 [frames], /type float32
// [particles], optional /velocities, /density, /pressure; box, time step, log step and provenance
// as attributes of the root group. Plain HDF5: h5py opens it without owval.
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <type_traits>

#include "hdf5_chunks.hpp"
#include "hdf5_handle.hpp"
#include "hdf5_preflight.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/contained.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/input_file.hpp"
#include "owval/base/mapped_file.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval {
namespace {

using internal::Handle;

void SilenceHdf5Errors() { internal::PrepareHdf5(); }

// Frames [first, first + count) of the per-frame field `name` ("positions", "velocities",
// "density", "pressure") into `out`, frame after frame.
using FillFrames =
    std::function<void(const char* name, std::size_t first, std::size_t count, float* out)>;

void Check(herr_t status, const std::string& file, const std::string& what) {
  if (status < 0) throw InputError(file, 0, "HDF5: " + what);
}

bool Nonempty(const std::vector<hsize_t>& dims) {
  return std::all_of(dims.begin(), dims.end(), [](hsize_t d) { return d > 0; });
}

hid_t CreateDataset(hid_t file, const char* name, hid_t type, const std::vector<hsize_t>& dims,
                    const std::vector<hsize_t>& chunk, int level, const std::string& path) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle plist(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  // No object timestamps: identical trajectories give identical bytes (issue 18 item 15).
  Check(H5Pset_obj_track_times(plist, false), path, "set track times");
  if (!chunk.empty() && Nonempty(dims)) {
    Check(H5Pset_chunk(plist, static_cast<int>(chunk.size()), chunk.data()), path, "set chunk");
    Check(H5Pset_shuffle(plist), path, "set shuffle");
    Check(H5Pset_deflate(plist, static_cast<unsigned>(level)), path, "set deflate");
  }
  const hid_t set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT);
  if (set < 0) throw InputError(path, 0, std::string("HDF5: cannot create dataset ") + name);
  return set;
}

void WriteDataset(hid_t file, const char* name, hid_t type, const void* data,
                  const std::vector<hsize_t>& dims, const std::vector<hsize_t>& chunk, int level,
                  const std::string& path) {
  Handle set(CreateDataset(file, name, type, dims, chunk, level, path), H5Dclose);
  if (Nonempty(dims)) Check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), path, name);
}

struct FieldShape {
  std::vector<hsize_t> dims, chunk;
};

FieldShape FrameFieldShape(hsize_t frames, hsize_t particles, int components,
                           const Hdf5WriteOptions& o) {
  std::vector<hsize_t> dims = {frames, particles};
  // Chunks span several frames of a block of particles, so the same particle's bytes in
  // successive frames sit a few KiB apart after shuffling: deflate's 32 KiB window then finds the
  // particles that did not move (every boundary particle) and reads decompress at memcpy speed.
  std::vector<hsize_t> chunk = {
      std::max<hsize_t>(1, std::min<hsize_t>(o.frames_per_chunk, frames)),
      std::max<hsize_t>(1, std::min<hsize_t>(o.particles_per_chunk, particles))};
  if (components > 1) {
    dims.push_back(static_cast<hsize_t>(components));
    chunk.push_back(static_cast<hsize_t>(components));
  }
  return {dims, chunk};
}

void WriteFrameField(hid_t file, const char* name, const std::vector<float>& data, hsize_t frames,
                     hsize_t particles, int components, const Hdf5WriteOptions& o,
                     const std::string& path) {
  const FieldShape shape = FrameFieldShape(frames, particles, components, o);
  WriteDataset(file, name, H5T_NATIVE_FLOAT, data.data(), shape.dims, shape.chunk,
               o.compression_level, path);
}

// The same dataset, written a chunk's frames at a time from `fill` (frames [first, first + count)
// into its buffer): one block of frames in memory, and the file's bytes those of one write.
void WriteFrameFieldInBlocks(hid_t file, const char* name, const FillFrames& fill, hsize_t frames,
                             hsize_t particles, int components, const Hdf5WriteOptions& o,
                             const std::string& path) {
  const FieldShape shape = FrameFieldShape(frames, particles, components, o);
  Handle set(CreateDataset(file, name, H5T_NATIVE_FLOAT, shape.dims, shape.chunk,
                           o.compression_level, path),
             H5Dclose);
  if (!Nonempty(shape.dims)) return;
  const hsize_t block = shape.chunk[0], per_frame = particles * static_cast<hsize_t>(components);
  std::vector<float> buffer(block * per_frame);
  Handle file_space(H5Dget_space(set), H5Sclose);
  for (hsize_t first = 0; first < frames; first += block) {
    std::vector<hsize_t> start(shape.dims.size(), 0), count = shape.dims;
    start[0] = first;
    count[0] = std::min(block, frames - first);
    fill(name, first, count[0], buffer.data());
    Check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(),
                              nullptr),
          path, name);
    Handle memory(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr),
                  H5Sclose);
    Check(H5Dwrite(set, H5T_NATIVE_FLOAT, memory, file_space, H5P_DEFAULT, buffer.data()), path,
          name);
  }
}

void WriteStringAttribute(hid_t object, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, value.size() + 1);  // room for the terminating NUL
  H5Tset_strpad(type, H5T_STR_NULLTERM);
  H5Tset_cset(type, H5T_CSET_UTF8);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  H5Awrite(attr, type, value.c_str());
}

template <typename T>
void WriteNumericAttribute(hid_t object, const char* name, hid_t type, const T* values, hsize_t n) {
  Handle space(n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr), H5Sclose);
  Handle attr(H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  H5Awrite(attr, type, values);
}

}  // namespace

namespace {

// Writes one per-frame field's dataset ("positions", 3 values a particle, "velocities", 3,
// "density" or "pressure", 1) into the open file.
using WriteField = std::function<void(hid_t file, const char* name, int components)>;

// owval's HDF5 file: `t`'s box, steps, types, times and provenance (its per-frame arrays are not
// read), and the per-frame fields `fields` lists (asked once the positions are written), in the
// order WriteHdf5 has always written them.
void WriteHdf5File(const Trajectory& t, const std::function<std::vector<const char*>()>& fields,
                   const std::filesystem::path& path, const WriteField& write_field) {
  const std::lock_guard<std::recursive_mutex> lock(internal::Hdf5Mutex());
  SilenceHdf5Errors();
  AtomicOutput out(path);
  const std::string name = path.string();
  {
    Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
    Check(H5Pset_obj_track_times(fcpl, false), name, "set track times");  // the root group's
    Handle file(H5Fcreate(out.temporary_path().c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT),
                H5Fclose);
    if (!file.valid()) throw InputError(name, 0, "cannot create HDF5 file");
    const hsize_t frames = t.frame_count(), particles = t.particle_count();
    write_field(file, "positions", 3);
    WriteDataset(file, "time", H5T_NATIVE_DOUBLE, t.time_s.data(), {frames}, {}, 0, name);
    WriteDataset(file, "type", H5T_NATIVE_FLOAT, t.type.data(), {particles}, {}, 0, name);
    for (const char* field : fields())
      write_field(file, field, std::string(field) == "velocities" ? 3 : 1);
    const float box[6] = {t.box.xmin, t.box.xmax, t.box.ymin, t.box.ymax, t.box.zmin, t.box.zmax};
    WriteNumericAttribute(file, "box", H5T_NATIVE_FLOAT, box, 6);
    WriteNumericAttribute(file, "time_step_s", H5T_NATIVE_DOUBLE, &t.time_step_s, 1);
    WriteNumericAttribute(file, "log_step", H5T_NATIVE_INT, &t.log_step, 1);
    WriteStringAttribute(file, "format", "owval trajectory 1");
    WriteStringAttribute(file, "position_units",
                         "configuration units (metres = cu * simulation_scale)");
    for (const auto& [key, value] : t.provenance)
      WriteStringAttribute(file, "provenance:" + key, value);
    if (H5Fflush(file, H5F_SCOPE_LOCAL) < 0) throw InputError(name, 0, "HDF5 flush failed");
  }
  out.Commit();
}

std::vector<const char*> FieldsOf(const Trajectory& t) {
  std::vector<const char*> fields;
  if (t.has_velocities()) fields.push_back("velocities");
  if (t.has_density()) fields.push_back("density");
  if (t.has_pressure()) fields.push_back("pressure");
  return fields;
}

const std::vector<float>& FieldValues(const Trajectory& t, const std::string& name) {
  return name == "positions"    ? t.positions
         : name == "velocities" ? t.velocities
         : name == "density"    ? t.density
                                : t.pressure;
}

}  // namespace

void WriteHdf5(const Trajectory& t, const std::filesystem::path& path, const Hdf5WriteOptions& o) {
  t.CheckShape();
  const std::string name = path.string();
  WriteHdf5File(
      t, [&] { return FieldsOf(t); }, path,
      [&](hid_t file, const char* field, int components) {
        WriteFrameField(file, field, FieldValues(t, field), t.frame_count(), t.particle_count(),
                        components, o, name);
      });
}

void WriteHdf5(FrameSource& frames, const std::filesystem::path& path, const Hdf5WriteOptions& o) {
  const Trajectory& header = frames.header();
  const std::size_t particles = header.particle_count();
  // Positions are read alone; then the fields the source holds, which show in its frames (a
  // source with no frame has none).
  const auto fields = [&frames] {
    frames.ReadFields();
    return frames.frame_count() ? FieldsOf(frames.Frame(0).trajectory) : std::vector<const char*>{};
  };
  const FillFrames fill = [&](const char* field, std::size_t first, std::size_t count, float* out) {
    frames.CopyFrames(field, first, count, out);  // that dataset alone
  };
  const std::string name = path.string();
  WriteHdf5File(header, fields, path, [&](hid_t file, const char* field, int components) {
    WriteFrameFieldInBlocks(file, field, fill, header.frame_count(), particles, components, o,
                            name);
  });
}

namespace {

// std::vector value-initialises on one core, and most of that time is the kernel zeroing the
// fresh pages on first touch. Touching them first on all cores shares that out; the vector's own
// zero fill then runs over resident pages.
void TouchPagesInParallel(void* data, std::size_t bytes) {
  constexpr std::size_t kPage = 4096, kWorthIt = 16u << 20;
  if (bytes < kWorthIt) return;
  auto* p = static_cast<unsigned char*>(data);
  const std::ptrdiff_t pages = static_cast<std::ptrdiff_t>((bytes + kPage - 1) / kPage);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < pages; ++i) p[static_cast<std::size_t>(i) * kPage] = 0;
}

std::string ShapeText(const std::vector<hsize_t>& d) {
  std::string s;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (i) s.push_back('x');
    s.append(d[i] ? std::to_string(d[i]) : std::string("*"));
  }
  return s;
}

// Reads a dataset whose shape must be exactly `expected` (0 entries mean "any"), validated by
// InspectDataset before anything is allocated.
// A dry run (`dry`) makes every libhdf5 call the real read makes but decodes no chunk itself and
// uses no OpenMP: it runs in a child process first (ReadHdf5).
template <typename T>
std::vector<T> ReadDataset(hid_t file, const char* name, hid_t mem_type,
                           std::vector<hsize_t> expected, internal::FileBytes* bytes,
                           std::uintmax_t file_bytes, bool required, bool dry) {
  const std::string& path = bytes->path();
  const auto shape = internal::InspectDataset(file, name, path, file_bytes, sizeof(T), required);
  if (!shape) return {};
  const std::vector<hsize_t>& dims = shape->dims;
  bool shape_ok = dims.size() == expected.size();
  for (std::size_t i = 0; shape_ok && i < dims.size(); ++i)
    shape_ok = expected[i] == 0 || expected[i] == dims[i];
  if (!shape_ok)
    throw InputError(path, 0,
                     std::string("HDF5: /") + name + " has shape " + ShapeText(dims) +
                         ", expected " + ShapeText(expected));
  Handle set(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  const std::size_t total = shape->elements;
  if constexpr (std::is_same_v<T, float>) {
    if (dry && total > 0 && internal::ReadDeflatedChunksInParallel(file, set, bytes, dims, nullptr))
      return {};
  }
  std::vector<T> data;
  data.reserve(total);
  AdviseHugePages(data.data(), total * sizeof(T));
  if (!dry) TouchPagesInParallel(data.data(), total * sizeof(T));
  data.resize(total);
  if constexpr (std::is_same_v<T, float>) {
    if (total > 0 && internal::ReadDeflatedChunksInParallel(file, set, bytes, dims, data.data()))
      return data;
  }
  if (total > 0 && H5Dread(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    throw InputError(path, 0,
                     std::string("HDF5: cannot read /") + name + " (truncated or corrupt file?)");
  return data;
}

// The provenance strings: scalar, fixed-length string attributes named "provenance:KEY".
void ReadProvenance(hid_t file, Trajectory& t, const std::string& path, std::uintmax_t file_bytes) {
  H5O_info_t info{};
  if (H5Oget_info2(file, &info, H5O_INFO_NUM_ATTRS) < 0)
    throw InputError(path, 0, "HDF5: cannot list the root group's attributes (corrupt?)");
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    Handle attr(H5Aopen_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT),
                H5Aclose);
    if (!attr.valid()) throw InputError(path, 0, "HDF5: cannot open a root attribute (corrupt?)");
    char name[256] = {};
    if (H5Aget_name(attr, sizeof name, name) < 0) continue;
    const std::string key(name);
    if (key.rfind("provenance:", 0) != 0) continue;
    Handle type(H5Aget_type(attr), H5Tclose);
    Handle space(H5Aget_space(attr), H5Sclose);
    if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0 ||
        H5Sget_simple_extent_npoints(space) != 1)
      continue;
    const std::size_t size = H5Tget_size(type);
    if (size == 0 || size > file_bytes)
      throw InputError(path, 0,
                       "HDF5: attribute " + key + " declares a string longer than the file");
    std::string value(size + 1, '\0');
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem, value.size());
    H5Tset_cset(mem, H5Tget_cset(type));
    if (H5Aread(attr, mem, value.data()) < 0)
      throw InputError(path, 0, "HDF5: cannot read attribute " + key);
    value.resize(std::strlen(value.c_str()));
    t.provenance[key.substr(11)] = value;
  }
}

}  // namespace

namespace {

// Box, time step and log step: root attributes of exactly the expected sizes, finite, positive.
void ReadScalars(hid_t file, Trajectory& t, const std::string& path) {
  float box[6];
  internal::ReadNumericAttribute(file, "box", H5T_NATIVE_FLOAT, box, 6, path);
  for (float v : box)
    if (!std::isfinite(v)) throw InputError(path, 0, "HDF5: attribute box is not finite");
  for (int axis = 0; axis < 3; ++axis)
    if (box[2 * axis + 1] < box[2 * axis])
      throw InputError(path, 0,
                       std::string("HDF5: attribute box: the ") + "xyz"[axis] +
                           " maximum is below its minimum (expected xmin, xmax, ymin, ymax, "
                           "zmin, zmax)");
  t.box = {box[0], box[1], box[2], box[3], box[4], box[5]};
  internal::ReadNumericAttribute(file, "time_step_s", H5T_NATIVE_DOUBLE, &t.time_step_s, 1, path);
  if (!(std::isfinite(t.time_step_s) && t.time_step_s > 0))
    throw InputError(path, 0, "HDF5: attribute time_step_s must be a positive finite number");
  double log_step = 0;  // read as a double: HDF5's own float-to-int conversion of NaN is undefined
  internal::ReadNumericAttribute(file, "log_step", H5T_NATIVE_DOUBLE, &log_step, 1, path);
  if (!(log_step >= 1 && log_step <= std::numeric_limits<int>::max() &&
        log_step == std::floor(log_step)))
    throw InputError(path, 0, "HDF5: attribute log_step must be a whole number from 1 to 2^31-1");
  t.log_step = static_cast<int>(log_step);
}

// Index of the first value that is not finite, or npos.
template <typename T>
std::size_t FirstNonFinite(const std::vector<T>& values) {
  std::size_t first = std::string::npos;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(values.size());
  // Small arrays on one thread: waking the pool costs more than the scan (and a spinning worker
  // slows the contained dry run's child on a busy machine).
#pragma omp parallel for reduction(min : first) schedule(static) if (n > (1 << 20))
  for (std::ptrdiff_t i = 0; i < n; ++i)
    if (!std::isfinite(values[std::size_t(i)])) first = std::min(first, std::size_t(i));
  return first;
}

void CheckFinite(const char* dataset, std::size_t first, const std::string& path) {
  if (first != std::string::npos)
    throw InputError(path, 0,
                     std::string("HDF5: /") + dataset + " value " + std::to_string(first) +
                         " is not finite (NaN or Inf)");
}

// A code KindOf would read as boundary though Sibernetic knows no such particle (1.4e6, 0, -3).
void CheckTypeCodes(const std::vector<float>& type, const std::string& path) {
  const auto bad = std::find_if_not(type.begin(), type.end(), IsSiberneticTypeCode);
  if (bad != type.end())
    throw InputError(path, 0,
                     "HDF5: /type row " + std::to_string(bad - type.begin()) + " is " +
                         FormatNumber(*bad) + ": " + kExpectedTypeCode);
}

// Names the frame, particle and coordinate of the first non-finite position.
void CheckFinitePositions(const Trajectory& t, const std::string& path) {
  const std::size_t first = FirstNonFinite(t.positions);
  if (first == std::string::npos) return;
  const std::size_t particles = t.particle_count();
  throw NonFiniteTrajectoryError(path, 0,
                                 internal::NonFinitePositionMessage(
                                     first / (particles * 3), first / 3 % particles, first % 3));
}

}  // namespace

namespace {

// dry: every libhdf5 call, nothing decoded (the contained run); frames: read the per-frame
// datasets (false: metadata, types and times only, for Hdf5FrameReader).
Trajectory ReadHdf5InProcess(const std::string& name, std::uintmax_t file_bytes, bool dry,
                             bool frames = true) {
  if (H5Fis_hdf5(name.c_str()) <= 0)
    throw InputError(name, 0, "not a readable HDF5 file (truncated or wrong format)");
  Handle file(H5Fopen(name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError(name, 0, "cannot open HDF5 file (truncated or corrupt?)");
  internal::FileBytes bytes(name);
  Trajectory t;
  ReadScalars(file, t, name);
  auto floats = [&](const char* dataset, std::vector<hsize_t> shape, bool required) {
    return ReadDataset<float>(file, dataset, H5T_NATIVE_FLOAT, std::move(shape), &bytes, file_bytes,
                              required, dry);
  };
  t.type = floats("type", {0}, true);
  if (t.type.empty())
    throw InputError(name, 0, "HDF5: /type is empty: expected at least one particle");
  t.time_s =
      ReadDataset<double>(file, "time", H5T_NATIVE_DOUBLE, {0}, &bytes, file_bytes, true, dry);
  const hsize_t count = t.time_s.size(), particles = t.type.size();
  if (frames) {
    t.positions = floats("positions", {count, particles, 3}, true);
    t.velocities = floats("velocities", {count, particles, 3}, false);
    t.density = floats("density", {count, particles}, false);
    t.pressure = floats("pressure", {count, particles}, false);
  }
  ReadProvenance(file, t, name, file_bytes);
  // A trajectory cut short by an interrupted run (TrajectoryWriter::Abort) says so.
  if (H5Aexists(file, "partial") > 0) t.provenance["partial"].assign(1, '1');
  return t;
}

}  // namespace

namespace internal {

std::string NonFinitePositionMessage(std::size_t frame, std::size_t particle,
                                     std::size_t coordinate) {
  const char axis[] = {"xyz"[coordinate % 3], '\0'};
  return "HDF5: /positions of frame " + std::to_string(frame) + ", particle " +
         std::to_string(particle) + " (" + axis + ") is not finite (NaN or Inf)";
}

void DryRunHdf5Contained(const std::string& path) {
  const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
  SilenceHdf5Errors();
  RequireInputFile(path);
  const std::uintmax_t file_bytes = std::filesystem::file_size(path);
  RunContained(path, "HDF5: libhdf5", [&] { ReadHdf5InProcess(path, file_bytes, true); });
}

// The columns every reader checks before a frame is used: finite type codes in [1, 4), finite
// frame times that increase.
void CheckTypesAndTimes(const Trajectory& t, const std::string& path) {
  CheckFinite("type", FirstNonFinite(t.type), path);
  CheckTypeCodes(t.type, path);
  CheckFinite("time", FirstNonFinite(t.time_s), path);
  CheckFrameTimesIncrease(t.time_s, path, "HDF5: /time: ");
}

Trajectory ReadHdf5Metadata(const std::string& path) {
  const std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
  Trajectory t = ReadHdf5InProcess(path, std::filesystem::file_size(path), false, false);
  CheckTypesAndTimes(t, path);
  return t;
}

}  // namespace internal

Trajectory ReadHdf5(const std::filesystem::path& path) {
  const std::lock_guard<std::recursive_mutex> lock(internal::Hdf5Mutex());
  SilenceHdf5Errors();
  const std::string name = path.string();
  // Containment (docs/fuzzing.md): libhdf5 1.10.8 crashes on some corrupt metadata that no check
  // can see first, so every libhdf5 call is made once in a child process; only when that dry run
  // succeeds does owval make them in process and decode the chunks.
  internal::DryRunHdf5Contained(name);
  Trajectory t = ReadHdf5InProcess(name, std::filesystem::file_size(path), false);
  internal::CheckTypesAndTimes(t, name);
  CheckFinitePositions(t, name);
  return t;
}

FileFormat DetectFormat(const std::filesystem::path& path) {
  RequireInputFile(path);  // before open(): a FIFO would block it
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open file (missing or unreadable)");
  char signature[8] = {};
  in.read(signature, 8);
  if (in.gcount() == 8 && std::memcmp(signature, "\x89HDF\r\n\x1a\n", 8) == 0)
    return FileFormat::kHdf5;
  const std::string ext = path.extension().string();
  if (ext == ".h5" || ext == ".hdf5") return FileFormat::kHdf5;
  if (ext == ".wcon")  // read as text it said "expected box xmin, found '{'"
    throw InputError(path.string(), 0,
                     "is WCON, which owval writes but does not read as a trajectory; expected "
                     "owval HDF5 or Sibernetic text");
  return FileFormat::kSiberneticText;
}

Trajectory ReadTrajectory(const std::filesystem::path& path, const TextReadOptions& options,
                          TextReadReport* report) {
  Trajectory t;
  if (DetectFormat(path) == FileFormat::kHdf5) {
    t = ReadHdf5(path);
    if (report)
      report->description = "owval HDF5: " + std::to_string(t.frame_count()) + " frames, " +
                            std::to_string(t.particle_count()) + " particles";
  } else {
    t = ReadSiberneticText(path, options, report);
  }
  // The text format has no metadata: its name (PartialPath) says it is partial.
  if (IsPartialPath(path)) t.provenance["partial"].assign(1, '1');
  if (report && t.provenance.count("partial"))
    report->description += " (partial: an interrupted run's)";
  return t;
}

void WriteTrajectory(const Trajectory& t, const std::filesystem::path& path, TextLayout layout) {
  const std::string ext = path.extension().string();
  if (ext == ".h5" || ext == ".hdf5") {
    WriteHdf5(t, path);
  } else {
    WriteSiberneticText(t, path, layout == TextLayout::kAuto ? TextLayout::kOpenCL : layout);
  }
}

}  // namespace owval
