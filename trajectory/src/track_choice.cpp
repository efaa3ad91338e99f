#include "owval/trajectory/track_choice.hpp"

namespace owval {

Track TrackChoice::Over(Track base) const {
  if (particle) base = Track{*particle, "", base.axis};
  if (!group.empty()) base.group = group;
  if (axis) base.axis = ParseAxisName(*axis);
  return base;
}

}  // namespace owval
