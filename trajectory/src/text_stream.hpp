#pragma once
// Sibernetic text read frame by frame (frame_source.hpp): plain or gzip-compressed, in blocks.
#include <memory>
#include <string>

#include "owval/trajectory/frame_source.hpp"

namespace owval::internal {

// Scans the whole file once (every check ReadSiberneticText makes, nothing stored but frame 0
// and where each frame starts), then reads frames on demand. partial: the name says it is an
// interrupted run's (provenance "partial").
std::unique_ptr<FrameSource> OpenTextFrameSource(const std::string& path,
                                                 const TextReadOptions& options,
                                                 TextReadReport* report, bool partial);

}  // namespace owval::internal
