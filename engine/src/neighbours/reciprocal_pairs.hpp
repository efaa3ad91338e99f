#pragma once
// Reciprocal neighbour lists: a pair of moving particles kept only when each lists the other.
//
// Sibernetic's search (neighbour_grid.hpp) keeps at most 32 neighbours within h per particle.
// On demo1's lattice about 100 of the 343 moving particles have more than 32 within h in every
// step, so particle i can list j while j's list, full of nearer particles, leaves i out (about
// 100 liquid-liquid and 150 elastic-liquid pairs per step; docs/xpbd.md, "Where the x and z
// extents go"). A scheme that sums pair terms over each particle's own list then applies a
// term to i without its reaction on j: no longer equal and opposite, a net force and torque.
// Position-based fluids assume symmetric neighbourhoods: the Jacobi density update
// Δp_i = Σ_j (λ_i + λ_j)∇W_ij [Macklin & Müller 2013, Position based fluids, eq. 12] is the
// constraints' gradient Σ_k λ_k ∇_i C_k only when j ∈ N(i) ⇔ i ∈ N(j).
//
// The PCISPH path never calls this: it must keep Sibernetic's one-sided lists to match its digits.
#include "state/particle_state.hpp"

namespace owval::engine::internal {

// Removes from every moving particle's list the moving neighbours whose own list does not hold
// it (slot order kept, empty slots at the end) and rebuilds their boundary-slot masks. Pairs with
// boundary particles are kept: boundary particles never move. Returns how many entries it removed.
std::size_t KeepReciprocalPairs(ParticleState* state);

}  // namespace owval::engine::internal
