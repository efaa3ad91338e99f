#pragma once
// Neighbour search as Sibernetic does it (sphFluid.cl:286-465): a hash grid of cells 2h wide,
// eight cells searched per particle (its own and the seven toward the nearer half of it on each
// axis), and at most 32 neighbours within h kept by replacing the farthest. Boundary particles
// never move, so their cell lists are built once; moving particles are re-binned every step.
#include <cstdint>
#include <vector>

#include "owval/trajectory/trajectory.hpp"
#include "particle_state.hpp"
#include "sph_constants.hpp"

namespace owval::engine::internal {

class NeighbourGrid {
 public:
  NeighbourGrid(const Box& box, const SphConstants& k);

  // Bins the boundary particles (once).
  void SetStatic(const ParticleState& state);
  // Bins the moving particles at their current positions.
  void UpdateMoving(const ParticleState& state);
  // Fills particle i's kSlots neighbour slots from x(t).
  void FindNeighbours(const ParticleState& state, std::int32_t i, Neighbour* slots) const;

 private:
  int CellCoordinate(float x, int axis) const;
  int CellIndex(int cx, int cy, int cz) const { return cx + cy * nx_ + cz * nx_ * ny_; }

  Box box_;
  SphConstants k_;
  float cell_size_, cell_size_inverse_;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  // Particles per cell in ascending index order (compressed: offsets into a flat array).
  std::vector<std::int32_t> static_start_, static_items_;
  std::vector<std::int32_t> moving_start_, moving_items_;
};

}  // namespace owval::engine::internal
