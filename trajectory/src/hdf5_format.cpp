// owval's HDF5 layout (design notes §3): /positions float32 [frames, particles, 3] chunked along
// frames and deflate-compressed with the shuffle filter, /time float64 [frames], /type float32
// [particles], optional /velocities, /density, /pressure; box, time step, log step and provenance
// as attributes of the root group. Plain HDF5: h5py opens it without owval.
#include <hdf5.h>

#include <malloc.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <type_traits>

#include "hdf5_chunks.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/mapped_file.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval {
namespace {

// Closes an HDF5 handle when it leaves scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void SilenceHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

void Check(herr_t status, const std::string& file, const std::string& what) {
  if (status < 0) throw InputError(file, 0, "HDF5: " + what);
}

void WriteDataset(hid_t file, const char* name, hid_t type, const void* data,
                  const std::vector<hsize_t>& dims, const std::vector<hsize_t>& chunk, int level,
                  const std::string& path) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle plist(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  const bool nonempty = std::all_of(dims.begin(), dims.end(), [](hsize_t d) { return d > 0; });
  if (!chunk.empty() && nonempty) {
    Check(H5Pset_chunk(plist, static_cast<int>(chunk.size()), chunk.data()), path, "set chunk");
    Check(H5Pset_shuffle(plist), path, "set shuffle");
    Check(H5Pset_deflate(plist, static_cast<unsigned>(level)), path, "set deflate");
  }
  Handle set(H5Dcreate2(file, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT), H5Dclose);
  if (!set.valid()) throw InputError(path, 0, std::string("HDF5: cannot create dataset ") + name);
  if (nonempty) Check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), path, name);
}

void WriteFrameField(hid_t file, const char* name, const std::vector<float>& data, hsize_t frames,
                     hsize_t particles, int components, const Hdf5WriteOptions& o,
                     const std::string& path) {
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
  WriteDataset(file, name, H5T_NATIVE_FLOAT, data.data(), dims, chunk, o.compression_level, path);
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

void WriteHdf5(const Trajectory& t, const std::filesystem::path& path, const Hdf5WriteOptions& o) {
  t.CheckShape();
  SilenceHdf5Errors();
  AtomicOutput out(path);
  const std::string name = path.string();
  {
    Handle file(H5Fcreate(out.temporary_path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                H5Fclose);
    if (!file.valid()) throw InputError(name, 0, "cannot create HDF5 file");
    const hsize_t frames = t.frame_count(), particles = t.particle_count();
    WriteFrameField(file, "positions", t.positions, frames, particles, 3, o, name);
    WriteDataset(file, "time", H5T_NATIVE_DOUBLE, t.time_s.data(), {frames}, {}, 0, name);
    WriteDataset(file, "type", H5T_NATIVE_FLOAT, t.type.data(), {particles}, {}, 0, name);
    if (t.has_velocities())
      WriteFrameField(file, "velocities", t.velocities, frames, particles, 3, o, name);
    if (t.has_density()) WriteFrameField(file, "density", t.density, frames, particles, 1, o, name);
    if (t.has_pressure())
      WriteFrameField(file, "pressure", t.pressure, frames, particles, 1, o, name);
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

// Reads a dataset whose shape must be exactly `expected` (0 entries mean "any").
template <typename T>
std::vector<T> ReadDataset(hid_t file, const char* name, hid_t mem_type,
                           std::vector<hsize_t> expected, internal::FileBytes* bytes,
                           bool required) {
  const std::string& path = bytes->path();
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0) {
    if (required) throw InputError(path, 0, std::string("HDF5: missing dataset /") + name);
    return {};
  }
  Handle set(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  Handle space(H5Dget_space(set), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  bool shape_ok = dims.size() == expected.size();
  for (std::size_t i = 0; shape_ok && i < dims.size(); ++i)
    shape_ok = expected[i] == 0 || expected[i] == dims[i];
  if (!shape_ok) {
    auto shape = [](const std::vector<hsize_t>& d) {
      std::string s;
      for (std::size_t i = 0; i < d.size(); ++i) {
        if (i) s.push_back('x');
        s.append(d[i] ? std::to_string(d[i]) : std::string("*"));
      }
      return s;
    };
    const std::string got = shape(dims), want = shape(expected);
    throw InputError(path, 0,
                     std::string("HDF5: /") + name + " has shape " + got + ", expected " + want);
  }
  std::size_t total = 1;
  for (hsize_t d : dims) total *= d;
  std::vector<T> data;
  data.reserve(total);
  AdviseHugePages(data.data(), total * sizeof(T));
  TouchPagesInParallel(data.data(), total * sizeof(T));
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

void ReadAttributes(hid_t file, Trajectory& t, const std::string& path) {
  auto numeric = [&](const char* name, hid_t type, void* out) {
    if (H5Aexists(file, name) <= 0)
      throw InputError(path, 0, std::string("HDF5: missing attribute ") + name);
    Handle attr(H5Aopen(file, name, H5P_DEFAULT), H5Aclose);
    if (H5Aread(attr, type, out) < 0)
      throw InputError(path, 0, std::string("HDF5: cannot read attribute ") + name);
  };
  float box[6];
  numeric("box", H5T_NATIVE_FLOAT, box);
  t.box = {box[0], box[1], box[2], box[3], box[4], box[5]};
  numeric("time_step_s", H5T_NATIVE_DOUBLE, &t.time_step_s);
  numeric("log_step", H5T_NATIVE_INT, &t.log_step);
  H5O_info_t info;
  H5Oget_info2(file, &info, H5O_INFO_NUM_ATTRS);
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    Handle attr(H5Aopen_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT),
                H5Aclose);
    char name[256] = {};
    H5Aget_name(attr, sizeof name, name);
    const std::string key(name);
    if (key.rfind("provenance:", 0) != 0) continue;
    Handle type(H5Aget_type(attr), H5Tclose);
    if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0) continue;
    std::string value(H5Tget_size(type) + 1, '\0');
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

// HDF5 allocates and frees a buffer per chunk. With glibc's default thresholds, buffers of a few
// MiB are fresh mmaps (or trimmed heap) every time, and page faults then cost more than inflating
// the data. Keeping such buffers on the heap makes reads several times faster.
void KeepChunkBuffersOnHeap() {
  static const bool once = [] {
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    return true;
  }();
  (void)once;
}

Trajectory ReadHdf5(const std::filesystem::path& path) {
  SilenceHdf5Errors();
  KeepChunkBuffersOnHeap();
  const std::string name = path.string();
  if (!std::filesystem::exists(path)) throw InputError(name, 0, "cannot open file (missing)");
  if (H5Fis_hdf5(name.c_str()) <= 0)
    throw InputError(name, 0, "not a readable HDF5 file (truncated or wrong format)");
  Handle file(H5Fopen(name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError(name, 0, "cannot open HDF5 file (truncated or corrupt?)");
  internal::FileBytes bytes(name);
  Trajectory t;
  t.type = ReadDataset<float>(file, "type", H5T_NATIVE_FLOAT, {0}, &bytes, true);
  t.time_s = ReadDataset<double>(file, "time", H5T_NATIVE_DOUBLE, {0}, &bytes, true);
  const hsize_t frames = t.time_s.size(), particles = t.type.size();
  if (particles == 0)
    throw InputError(name, 0, "HDF5: /type is empty: expected at least one particle");
  t.positions =
      ReadDataset<float>(file, "positions", H5T_NATIVE_FLOAT, {frames, particles, 3}, &bytes, true);
  t.velocities = ReadDataset<float>(file, "velocities", H5T_NATIVE_FLOAT, {frames, particles, 3},
                                    &bytes, false);
  t.density =
      ReadDataset<float>(file, "density", H5T_NATIVE_FLOAT, {frames, particles}, &bytes, false);
  t.pressure =
      ReadDataset<float>(file, "pressure", H5T_NATIVE_FLOAT, {frames, particles}, &bytes, false);
  ReadAttributes(file, t, name);
  return t;
}

FileFormat DetectFormat(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open file (missing or unreadable)");
  char signature[8] = {};
  in.read(signature, 8);
  if (in.gcount() == 8 && std::memcmp(signature, "\x89HDF\r\n\x1a\n", 8) == 0)
    return FileFormat::kHdf5;
  const std::string ext = path.extension().string();
  if (ext == ".h5" || ext == ".hdf5") return FileFormat::kHdf5;
  return FileFormat::kSiberneticText;
}

Trajectory ReadTrajectory(const std::filesystem::path& path, const TextReadOptions& options,
                          TextReadReport* report) {
  if (DetectFormat(path) == FileFormat::kHdf5) {
    Trajectory t = ReadHdf5(path);
    if (report)
      report->description = "owval HDF5: " + std::to_string(t.frame_count()) + " frames, " +
                            std::to_string(t.particle_count()) + " particles";
    return t;
  }
  return ReadSiberneticText(path, options, report);
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
