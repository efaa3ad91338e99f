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
std::unique_ptr<TrajectoryWriter> ResumeTextWriter(const std::filesystem::path& destination,
                                                   const TrajectoryHeader& header,
                                                   TextLayout layout,
                                                   const WriterCheckpoint& checkpoint);
std::unique_ptr<TrajectoryWriter> ResumeHdf5Writer(const std::filesystem::path& destination,
                                                   const TrajectoryHeader& header,
                                                   const Hdf5WriteOptions& options,
                                                   const WriterCheckpoint& checkpoint);
// ResumeTextWriter's and ResumeHdf5Writer's refusals, changing nothing (CheckResumable).
void CheckTextResumable(const std::filesystem::path& destination,
                        const WriterCheckpoint& checkpoint);
void CheckHdf5Resumable(const std::filesystem::path& destination, const TrajectoryHeader& header,
                        const WriterCheckpoint& checkpoint);
// The file a checkpoint names, or the partial one an interrupted run left; InputError if none.
std::filesystem::path CheckpointedFile(const std::filesystem::path& destination,
                                       const WriterCheckpoint& checkpoint);

}  // namespace owval::internal
