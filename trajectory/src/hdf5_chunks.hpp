#pragma once
// Parallel read of the float datasets WriteHdf5 writes: chunked, shuffle then deflate. HDF5's own
// filter pipeline inflates one chunk at a time on one core; here the chunks' file addresses come
// from HDF5, their bytes from a memory map, and all cores inflate, un-shuffle and place them.
#include <hdf5.h>

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

}  // namespace owval::internal
