#include "hdf5_preflight.hpp"

#include <string>

#include "hdf5_handle.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/memory_budget.hpp"
#include "zlib_chunk.hpp"

namespace owval::internal {
namespace {

[[noreturn]] void Refuse(const std::string& path, const std::string& what) {
  throw InputError(path, 0, "HDF5: " + what);
}

void CheckObjectIsDataset(hid_t file, const std::string& dataset, const std::string& path) {
  H5O_info_t info{};
  if (H5Oget_info_by_name2(file, dataset.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0)
    Refuse(path, "cannot inspect " + dataset + " (corrupt object header?)");
  if (info.type != H5O_TYPE_DATASET) Refuse(path, dataset + " is not a dataset");
}

void CheckElementType(hid_t set, const std::string& dataset, const std::string& path) {
  Handle type(H5Dget_type(set), H5Tclose);
  if (!type.valid()) Refuse(path, "cannot read the element type of " + dataset);
  const std::size_t size = H5Tget_size(type);
  if (H5Tget_class(type) != H5T_FLOAT || (size != 4 && size != 8))
    Refuse(path, dataset + " does not hold 4- or 8-byte floating-point numbers");
}

std::vector<hsize_t> SimpleDims(hid_t set, const std::string& dataset, const std::string& path) {
  Handle space(H5Dget_space(set), H5Sclose);
  if (!space.valid() || H5Sget_simple_extent_type(space) != H5S_SIMPLE)
    Refuse(path, dataset + " has no simple dataspace (scalar, null or corrupt)");
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 1 || rank > 3) Refuse(path, dataset + " has rank " + std::to_string(rank));
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (H5Sget_simple_extent_dims(space, dims.data(), nullptr) != rank)
    Refuse(path, "cannot read the dimensions of " + dataset);
  return dims;
}

// Filters libhdf5 applies on the fallback path; anything else (szip, n-bit, scale-offset, a
// plugin) is not part of owval's layout.
void CheckFiltersAndChunk(hid_t set, const std::vector<hsize_t>& dims, std::size_t element_bytes,
                          const std::string& dataset, const std::string& path) {
  Handle dcpl(H5Dget_create_plist(set), H5Pclose);
  if (!dcpl.valid()) Refuse(path, "cannot read the storage properties of " + dataset);
  const int filters = H5Pget_nfilters(dcpl);
  if (filters < 0 || filters > 3) Refuse(path, dataset + " has an unexpected filter pipeline");
  for (int f = 0; f < filters; ++f) {
    unsigned flags = 0, config = 0;
    std::size_t values = 0;
    const H5Z_filter_t id =
        H5Pget_filter2(dcpl, unsigned(f), &flags, &values, nullptr, 0, nullptr, &config);
    if (id != H5Z_FILTER_SHUFFLE && id != H5Z_FILTER_DEFLATE && id != H5Z_FILTER_FLETCHER32)
      Refuse(path, dataset + " uses HDF5 filter " + std::to_string(id) +
                       " (owval reads shuffle, deflate and fletcher32 only)");
  }
  if (H5Pget_layout(dcpl) != H5D_CHUNKED) return;
  std::vector<hsize_t> chunk(dims.size());
  if (H5Pget_chunk(dcpl, int(dims.size()), chunk.data()) != int(dims.size()))
    Refuse(path, dataset + " has a chunk shape of another rank");
  std::size_t chunk_bytes = element_bytes;
  for (hsize_t c : chunk) {
    if (c == 0) Refuse(path, dataset + " has an empty chunk shape");
    chunk_bytes = SaturatingProduct(chunk_bytes, c);
  }
  if (chunk_bytes > (std::size_t{4} << 30))
    Refuse(path, dataset + " declares chunks of " + std::to_string(chunk_bytes) +
                     " bytes (HDF5 allows at most 4 GiB)");
  CheckAllocation(chunk_bytes, path, dataset + " chunk");
}

}  // namespace

std::optional<DatasetShape> InspectDataset(hid_t file, const char* name, const std::string& path,
                                           std::uintmax_t file_bytes,
                                           std::size_t memory_element_bytes, bool required) {
  const std::string dataset = std::string("/") + name;
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0) {
    if (required) Refuse(path, "missing dataset " + dataset);
    return std::nullopt;
  }
  CheckObjectIsDataset(file, dataset, path);
  Handle set(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  if (!set.valid()) Refuse(path, "cannot open dataset " + dataset + " (corrupt?)");
  CheckElementType(set, dataset, path);
  DatasetShape shape;
  shape.dims = SimpleDims(set, dataset, path);
  Handle type(H5Dget_type(set), H5Tclose);
  const std::size_t stored_element_bytes = H5Tget_size(type);
  CheckFiltersAndChunk(set, shape.dims, stored_element_bytes, dataset, path);
  shape.elements = 1;
  for (hsize_t d : shape.dims) shape.elements = SaturatingProduct(shape.elements, d);
  const std::size_t stored = SaturatingProduct(shape.elements, stored_element_bytes);
  Handle dcpl(H5Dget_create_plist(set), H5Pclose);
  const bool chunked = H5Pget_layout(dcpl) == H5D_CHUNKED;
  const std::size_t capacity =
      SaturatingProduct(static_cast<std::size_t>(file_bytes), chunked ? kMaxDeflateRatio : 1);
  if (stored > capacity)
    Refuse(path, dataset + " declares " + std::to_string(shape.elements) + " values (" +
                     (stored == SIZE_MAX ? std::string("over 2^64") : std::to_string(stored)) +
                     " bytes), more than the " + std::to_string(file_bytes) +
                     "-byte file can hold");
  CheckAllocation(SaturatingProduct(shape.elements, memory_element_bytes), path, dataset);
  return shape;
}

void ReadNumericAttribute(hid_t object, const char* name, hid_t mem_type, void* out, hssize_t count,
                          const std::string& path) {
  const std::string attribute = std::string("attribute ") + name;
  if (H5Aexists(object, name) <= 0) Refuse(path, "missing " + attribute);
  Handle attr(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) Refuse(path, "cannot open " + attribute);
  Handle space(H5Aget_space(attr), H5Sclose);
  const hssize_t values = space.valid() ? H5Sget_simple_extent_npoints(space) : -1;
  if (values != count)
    Refuse(path, attribute + " has " + std::to_string(values) + " values, expected " +
                     std::to_string(count));
  Handle type(H5Aget_type(attr), H5Tclose);
  const H5T_class_t kind = type.valid() ? H5Tget_class(type) : H5T_NO_CLASS;
  if (kind != H5T_FLOAT && kind != H5T_INTEGER) Refuse(path, attribute + " is not numeric");
  if (H5Aread(attr, mem_type, out) < 0) Refuse(path, "cannot read " + attribute);
}

}  // namespace owval::internal
