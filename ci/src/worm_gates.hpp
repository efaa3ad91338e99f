#pragma once
// The worm's gates (DD001, issue 15), added to quick-test and validate when the run is a worm:
//  - quick-test: the directory holds a .wcon that a WCON reader accepts;
//  - validate: Tier-3, each kinematic metric of the candidate against Palyanov et al. 2018's
//    baseline within +-15% (kinematics/baseline.hpp), and the candidate's kinematics within 5% of
//    the reference's.
#include <filesystem>
#include <vector>

#include "owval/ci/gates.hpp"
#include "owval/kinematics/skeleton.hpp"

namespace owval::ci::internal {

std::vector<GateResult> WormQuickTestGates(const std::filesystem::path& directory);
// The skeletons of every frame (kinematics::SkeletonsFromTrajectory, or SkeletonAt frame by
// frame); reference: null when the reference is not a worm.
std::vector<GateResult> WormValidateGates(const kinematics::SkeletonSeries* reference,
                                          const kinematics::SkeletonSeries& candidate);

}  // namespace owval::ci::internal
