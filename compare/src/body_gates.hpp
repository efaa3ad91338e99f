#pragma once
// Scene gates beyond particles and group centroids, for scenes that have the body they measure:
//  - a worm (kinematics::IsWorm on both runs): worm.centre_of_mass (max 3-D distance over the
//    paired frames, of the box; the centroid_distance threshold), worm.span and
//    worm.cross_section_diameter (max relative difference; the body_shape threshold), measured by
//    kinematics::MeasureBodyShape. Ports that let the worm sink or swell fail here
//    (openworm/sibernetic#238);
//  - liquid over an elastic sheet (demo2: every elastic particle on one horizontal plane at the
//    first frame, with liquid above it): liquid.fraction_above_membrane, the max difference of
//    the fraction of liquid particles above the sheet's mean height (the
//    membrane_liquid_fraction threshold). A leaking membrane fails here.
// Scenes without such a body get none of these gates.
#include <cstddef>
#include <utility>
#include <vector>

#include "owval/compare/parity.hpp"

namespace owval::compare::internal {

void GateBodies(const Trajectory& reference, const Trajectory& candidate,
                const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                const ParityGates& gates, ParityReport* report);

}  // namespace owval::compare::internal
