#pragma once
// A track as a user gives it (owval's --particle, --group and --axis flags): only the parts that
// were given, laid over a default track (a scenario manifest's, or particle 0 y) by Over.
#include <cstddef>
#include <optional>
#include <string>

#include "owval/trajectory/track.hpp"

namespace owval {

struct TrackChoice {
  std::optional<std::size_t> particle;
  std::string group;                // elastic | liquid | all (excludes the particle)
  std::optional<std::string> axis;  // x | y | z

  bool given() const { return particle || !group.empty(); }
  // `base` with what was given: a particle replaces a group, a group a particle; the axis is
  // base's unless given (InputError for anything but x, y, z).
  Track Over(Track base) const;
};

}  // namespace owval
