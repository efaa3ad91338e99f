#pragma once
// Shared argument handling of the commands that run simulations.
#include <memory>
#include <string>
#include <vector>

#include "owval/engine/config.hpp"
#include "owval/sgd/fit.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::cli {

// A scenario name (a manifest in the data directory's scenarios/) or a configuration file.
engine::SiberneticConfig ResolveConfig(const std::string& name_or_path);

// A trajectory named on the command line: any format, the text layout detected unless `layout`
// (auto | opencl | native) says otherwise, the progress line following --quiet.
Trajectory ReadTrajectoryArgument(const std::string& path, const std::string& layout = "auto",
                                  TextReadReport* report = nullptr);

// The same, read frame by frame (compare, render: memory O(particles), whatever the length).
std::unique_ptr<FrameSource> OpenTrajectoryArgument(const std::string& path,
                                                    const std::string& layout = "auto",
                                                    TextReadReport* report = nullptr);

// "0,15,100,200" → indices; InputError naming `flag` on anything else (an empty list, a frame
// listed twice).
std::vector<std::size_t> ParseIndexList(const std::string& text, const std::string& flag);

}  // namespace owval::cli
