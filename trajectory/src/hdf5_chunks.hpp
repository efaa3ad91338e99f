#pragma once
// Parallel read of the float datasets WriteHdf5 writes: chunked, shuffle then deflate. HDF5's own
// filter pipeline inflates one chunk at a time on one core; here the chunks' file addresses come
// from HDF5, their bytes from a memory map, and all cores inflate, un-shuffle and place them.
#include <hdf5.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "owval/base/mapped_file.hpp"

namespace owval::internal {

// The file's bytes, mapped the first time a dataset needs them and shared by the datasets after.
class FileBytes {
 public:
  explicit FileBytes(std::string path) : path_(std::move(path)) {}
  const std::string& path() const { return path_; }
  std::string_view bytes() {
    if (!map_) map_.emplace(path_);
    return map_->text();
  }

 private:
  std::string path_;
  std::optional<MappedFile> map_;
};

// Reads float dataset `set` of shape `dims` (2 or 3 axes) into `out` (already sized). Returns
// false, having read nothing, when the dataset is stored any other way (not chunked, other
// filters, another element type, a user block): the caller then uses H5Dread. Throws InputError
// naming the file when a chunk is truncated or does not inflate to its size. With out == nullptr,
// a dry run: walks the chunk index (every libhdf5 call the real read makes) and decodes nothing.
bool ReadDeflatedChunksInParallel(hid_t file, hid_t set, FileBytes* bytes,
                                  const std::vector<hsize_t>& dims, float* out);

struct ChunkScratch;  // one thread's decoder and buffers (hdf5_chunks.cpp)

// The streaming reader's path to the same datasets: one row of chunks (every chunk that starts at
// a given frame) at a time, each chunk's stored bytes read with pread and inflated by libdeflate
// into buffers kept from row to row. libhdf5's filter pipeline allocates fresh buffers for every
// chunk it inflates (a fresh mapping each under ASan: a sanitized checklist made 1.1 million page
// faults there); a memory map would make the process's resident size grow with the file read.
// Memory: one row of stored and inflated chunks per thread, whatever the number of frames.
class DeflatedChunkRows {
 public:
  // nullptr when dataset `set` (shape `dims`, rank 2 or 3) of `file` is stored any other way: the
  // caller then reads it with H5Dread. Throws InputError naming `path` when it cannot be opened.
  // `set` stays the caller's: it must stay open while the rows are read.
  static std::unique_ptr<DeflatedChunkRows> Open(hid_t file, hid_t set, const std::string& path,
                                                 const std::vector<hsize_t>& dims);
  ~DeflatedChunkRows();
  DeflatedChunkRows(const DeflatedChunkRows&) = delete;
  DeflatedChunkRows& operator=(const DeflatedChunkRows&) = delete;

  std::size_t frames_per_row() const { return std::size_t(shape_[0]); }
  // Frames [first, first + frames_per_row()) (fewer at the dataset's end) into `out`, frame after
  // frame; `first` a multiple of frames_per_row(). Throws InputError naming the file and `first`
  // ("HDF5: cannot read frame F: ...") when a chunk is missing from the index, truncated or does
  // not inflate to its size.
  void Read(std::size_t first, float* out);

 private:
  DeflatedChunkRows(hid_t set, std::string path, std::vector<hsize_t> dims,
                    std::vector<hsize_t> shape, int fd, std::uintmax_t file_bytes);

  hid_t set_;
  std::string path_;
  std::vector<hsize_t> dims_, shape_;
  int fd_;
  std::uintmax_t file_bytes_;
  std::vector<std::unique_ptr<ChunkScratch>> scratch_;  // one a thread
};

}  // namespace owval::internal
