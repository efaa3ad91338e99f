#pragma once
#include "owval/trajectory/trajectory.hpp"

namespace owval::render::internal {

// Largest distance of a non-boundary particle from the non-boundary centroid at a frame, as the
// half-height a panel of this aspect (width / height) must show when z runs up the panel and x
// across it: max(|dz|, |dx| / aspect), in cu (at least 1).
float WormHalfExtent(const Trajectory& trajectory, std::size_t frame, float aspect);

}  // namespace owval::render::internal
