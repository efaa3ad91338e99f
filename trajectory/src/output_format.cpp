#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval {

void CheckTrajectoryOutput(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext != ".h5" && ext != ".hdf5" && ext != ".txt" && ext != ".wcon" && ext != ".zarr")
    throw InputError(path.string(), 0,
                     "unknown output format '" + ext +
                         "': owval writes .h5/.hdf5 (HDF5), .txt (Sibernetic text), .wcon (WCON) "
                         "and .zarr (OME-Zarr)");
  // An OME-Zarr store is a directory: only its parent must be writable.
  if (ext == ".zarr")
    CheckOutputDirectory(path);
  else
    CheckOutputPath(path);
}

}  // namespace owval
