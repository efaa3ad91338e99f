#pragma once
// Containment of HDF5 files from outside (issue 18 items 1, 6, 7), by pre-flight validation:
// before owval reads a value or sizes a buffer, it checks what the file's metadata declares
// against what owval's layout allows and what the file can hold. libhdf5 1.10 itself crashes on
// some corrupt metadata (in H5Dread's filters, in attribute reads into a caller's buffer sized
// from assumptions); the checks here refuse those files first:
//  - each dataset is a dataset (not a group or a named type), a simple dataspace of the expected
//    rank, of floating-point elements of 4 or 8 bytes, with no filter but shuffle, deflate and
//    Fletcher-32 (the filters libhdf5 decodes itself on the fallback path);
//  - its size cannot exceed what its file holds: element count x element size at most the file's
//    size, or 1032 times it (deflate's maximum ratio) when chunked, and within the memory budget;
//    a chunk's size is at most 4 GiB (HDF5's own limit) and within the budget;
//  - each numeric attribute has exactly the number of values owval reads, of a numeric class.
// What remains (a libhdf5 bug reached by metadata that passes these checks) is not contained by
// a child process: owval's readers run in-process so that the parallel chunk path keeps its speed,
// and the fuzz target for this reader (fuzz/) keeps hunting for such inputs.
#include <hdf5.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "owval/trajectory/trajectory.hpp"

namespace owval::internal {

struct DatasetShape {
  std::vector<hsize_t> dims;
  std::size_t elements = 0;
};

// Validates dataset /name as above. Returns nullopt when it is absent and not required; throws
// InputError naming the file and the dataset otherwise.
std::optional<DatasetShape> InspectDataset(hid_t file, const char* name, const std::string& path,
                                           std::uintmax_t file_bytes,
                                           std::size_t memory_element_bytes, bool required);

// Reads numeric attribute `name` of `object`: exactly `count` values of a numeric class into
// `out` (count values of mem_type). Throws InputError naming the file and attribute otherwise.
void ReadNumericAttribute(hid_t object, const char* name, hid_t mem_type, void* out, hssize_t count,
                          const std::string& path);

// Makes every libhdf5 call ReadHdf5 makes, decoding nothing, in a forked child (RunContained):
// throws InputError when the file is refused or crashes libhdf5. Defined in hdf5_format.cpp.
void DryRunHdf5Contained(const std::string& path);
// Box, time step, log step, types, times and provenance, positions not read (after a dry run).
Trajectory ReadHdf5Metadata(const std::string& path);
// "HDF5: /positions of frame F, particle P (x) is not finite (NaN or Inf)": the record of a failed
// simulation (NonFiniteTrajectoryError's message), named where a contributor can find it. Defined
// in hdf5_format.cpp.
std::string NonFinitePositionMessage(std::size_t frame, std::size_t particle,
                                     std::size_t coordinate);

}  // namespace owval::internal
