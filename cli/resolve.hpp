#pragma once
// Configurations and trajectories named on the command line: a scenario name is looked up in the
// data directory, and a trajectory's progress line follows --quiet.
#include <memory>
#include <string>

#include "command.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::cli {

// A scenario name (a manifest in the data directory's scenarios/) or a configuration file.
inline engine::SiberneticConfig ResolveConfig(const std::string& name_or_path) {
  return scenarios::ResolveConfig(name_or_path, DataDir());
}

// How a trajectory named on the command line is read: any format, the text layout detected
// unless `layout` (auto | opencl | native) says otherwise.
inline TextReadOptions Reading(const std::string& layout = "auto") {
  return {ParseLayout(layout), QuietMode()};
}
// A trajectory named on the command line, read frame by frame: memory O(particles), whatever the
// length (no command reads one whole).
inline std::unique_ptr<FrameSource> OpenTrajectoryArgument(const std::string& path) {
  return OpenFrameSource(path, Reading());
}

}  // namespace owval::cli
