#pragma once
// Boundary handling after Ihmsen et al. 2010, as Sibernetic applies it (sphFluid.cl:756-818).
//
//   [IAGT10] M. Ihmsen, N. Akinci, M. Gissler, M. Teschner. Boundary handling and adaptive
//            time-stepping for PCISPH. VRIPHYS 2010, pp. 79-88.
#include "kernels/sph_constants.hpp"
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Pushes a new position x (cu) of particle i out of the walls: boundary neighbours b from i's
// x(t) list weigh in with w_b = max(0, (r0 − |x − x_b|)/r0) [IAGT10 eq. 10]; x moves along the
// weighted normal, normalised over all four components of the boundary's velocity slot (its wall
// normal; the 4th component is whatever the file holds, gotcha 4), by Σw(r0 − d)/Σw [eq. 11].
// With v: the velocity's component into the wall, along the unnormalised normal, is removed and
// the velocity scaled by the friction factor 0.99 [eq. 12]. Reads state.boundary_slots[i], which
// NeighbourGrid::Refresh sets with i's list.
void CorrectAtWalls(const SphConstants& k, const ParticleState& state, std::int32_t i, Float4* x,
                    Float4* v);

}  // namespace owval::engine::internal
