#include "resolve.hpp"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/scenarios/scenario.hpp"

namespace owval::cli {

engine::SiberneticConfig ResolveConfig(const std::string& name_or_path) {
  return scenarios::ResolveConfig(name_or_path, DataDir());
}

Trajectory ReadTrajectoryArgument(const std::string& path, const std::string& layout,
                                  TextReadReport* report) {
  TextReadOptions options;
  options.layout = ParseLayout(layout);
  options.quiet = Flags().quiet;
  return ReadTrajectory(path, options, report);
}

std::unique_ptr<FrameSource> OpenTrajectoryArgument(const std::string& path,
                                                    const std::string& layout,
                                                    TextReadReport* report) {
  TextReadOptions options;
  options.layout = ParseLayout(layout);
  options.quiet = Flags().quiet;
  return OpenFrameSource(path, options, report);
}

std::vector<std::size_t> ParseIndexList(const std::string& text, const std::string& flag) {
  // An empty list ("" or a trailing comma) named nothing to render or gate: refused, as ",".
  if (text.empty() || text.back() == ',')
    throw InputError(flag + ": expected comma-separated frame indices, found '" + text + "'");
  std::vector<std::size_t> indices;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {  // digits only: stoul would take "-1" as 2^64 - 1 (and throws past 2^64)
      if (item.empty() || item.find_first_not_of("0123456789") != std::string::npos)
        throw std::invalid_argument(item);
      indices.push_back(std::stoul(item));
    } catch (const std::exception&) {
      throw InputError(flag + ": expected comma-separated frame indices, found '" + item + "'");
    }
    if (std::count(indices.begin(), indices.end(), indices.back()) > 1)
      throw InputError(flag + ": frame " + item + " is listed twice");
  }
  return indices;
}

}  // namespace owval::cli
