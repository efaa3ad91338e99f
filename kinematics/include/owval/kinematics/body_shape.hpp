#pragma once
// The worm body's gross shape at one frame, for backend parity: does a port keep the worm
// afloat, intact and at its length? (openworm/sibernetic issues #233-#239 ask ports to check
// this beside the particle-level gates.) Computed from the midline particles only (elastic
// particles with a midline sub-type code, midline.hpp), each bin being one cross-section ring:
//  - centre of mass: the mean position of those particles (equal masses), cu;
//  - span: the midline's arc length through the non-empty bins' means, head to tail, cu;
//  - cross-section diameter: twice the mean distance of a ring's particles from the ring's mean,
//    averaged over the rings of the middle half of the body (head and tail taper), cu.
#include <array>
#include <cstddef>

#include "owval/trajectory/trajectory.hpp"

namespace owval::kinematics {

struct BodyShape {
  std::array<double, 3> centre_of_mass_cu{};
  double span_cu = 0;
  double cross_section_diameter_cu = 0;
};

// InputError (kNotAWorm) when the trajectory has no worm body (IsWorm is false).
BodyShape MeasureBodyShape(const Trajectory& trajectory, std::size_t frame);

}  // namespace owval::kinematics
