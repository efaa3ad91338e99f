#pragma once
// The worm body's gross shape at one frame, for backend parity: does a port keep the worm
// afloat, intact and at its length? (openworm/sibernetic issues #233-#239 ask ports to check
// this beside the particle-level gates.) Computed from the midline particles only (elastic
// particles with a midline sub-type code, midline.hpp), each bin being one cross-section ring:
//  - centre of mass: the mean position of those particles (equal masses), cu;
//  - span: the midline's arc length through the non-empty bins' means, head to tail, cu;
//  - cross-section diameter: twice the mean distance of a ring's particles from the ring's mean,
//    averaged over the rings of the middle half of the body (head and tail taper), cu;
//  - ring diameters: the same diameter of every ring (bin) that holds at least 2 particles, 0 for
//    the others, cu. The mean over the middle half did not see the rest of the body: the worm's
//    tail quarter crushed to 5% of its thickness (ring means, centroid and midline unchanged)
//    passed every gate of owval compare.
#include <array>
#include <cstddef>

#include "owval/kinematics/midline.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::kinematics {

struct BodyShape {
  std::array<double, 3> centre_of_mass_cu{};
  double span_cu = 0;
  double cross_section_diameter_cu = 0;
  std::array<double, kMidlineBins> ring_diameter_cu{};  // bins 51..149, head first
};

// InputError (kNotAWorm) when the trajectory has no worm body (IsWorm is false).
BodyShape MeasureBodyShape(const Trajectory& trajectory, std::size_t frame);

}  // namespace owval::kinematics
