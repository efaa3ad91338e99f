#pragma once
// The two streaming writers behind OpenTrajectoryWriter (writer.hpp).
#include <filesystem>
#include <memory>

#include "owval/trajectory/writer.hpp"

namespace owval::internal {

std::unique_ptr<TrajectoryWriter> OpenTextWriter(const std::filesystem::path& destination,
                                                 const TrajectoryHeader& header, TextLayout layout);
std::unique_ptr<TrajectoryWriter> OpenHdf5Writer(const std::filesystem::path& destination,
                                                 const TrajectoryHeader& header,
                                                 const Hdf5WriteOptions& options);

}  // namespace owval::internal
