#pragma once
// Neighbour search as Sibernetic does it (sphFluid.cl:286-465): a hash grid of cells 2h wide,
// eight cells searched per particle (its own and the seven toward the nearer half of it on each
// axis), and at most 32 neighbours within h kept by replacing the farthest. Boundary particles
// never move, so their cell lists are built once; moving particles are re-binned every step.
#include <cstdint>
#include <vector>

#include "kernels/sph_constants.hpp"
#include "owval/trajectory/trajectory.hpp"
#include "state/particle_state.hpp"

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

  // The neighbours phase of a step: re-bins the moving particles, fills their lists, sets
  // state.active (moving particles, then the boundary particles some moving particle lists) and
  // fills the active boundary particles' lists.
  void Refresh(ParticleState* state, int threads);
  // Whether none of the cells particle i searches holds a moving particle (as of the last
  // Refresh): its list is then made of boundary particles only and does not change.
  bool SearchesOnlyBoundary(const ParticleState& state, std::int32_t i) const;
  // Whether the last Refresh computed particle i (moving, or a boundary particle next to one).
  bool IsActive(std::int32_t i) const {
    return std::size_t(i) < is_active_.size() && is_active_[std::size_t(i)] != 0;
  }

 private:
  int CellCoordinate(float x, int axis) const;
  // The eight cells particle position p searches, in Sibernetic's order (−1: outside the grid).
  void SearchCells(const Float4& p, int cells[8]) const;
  int CellIndex(int cx, int cy, int cz) const { return cx + cy * nx_ + cz * nx_ * ny_; }

  Box box_;
  SphConstants k_;
  float cell_size_, cell_size_inverse_;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  // One cell's candidates in ascending index order, with their x(t) in structure-of-arrays form
  // so that the distances of a whole cell are computed in one vectorised loop.
  struct Segment {
    const std::int32_t* index;
    const float *x, *y, *z;
    int count;
  };
  Segment CellSegment(int cell) const;
  // Bit n set when slot n holds a boundary particle.
  std::uint32_t BoundarySlots(const Neighbour* slots) const;
  // Fills particle i's list and its boundary-slot mask; a moving particle also marks the
  // boundary particles it lists.
  void ListSlots(ParticleState* state, std::int32_t i);
  // Sets state.active: the moving particles, then the boundary particles they list.
  void ListActive(ParticleState* state);
  // Rebuilds the merged segments of the cells that hold moving particles.
  void MergeCells(const ParticleState& state, const std::vector<int>& moving_cells);

  // Boundary particles per cell in ascending index order (offsets into flat arrays).
  std::vector<std::int32_t> static_start_, static_items_;
  std::vector<float> static_x_, static_y_, static_z_;
  std::vector<std::int32_t> moving_start_, moving_items_;
  // Cells with moving particles: merged (static + moving) candidates, rebuilt every step.
  std::vector<std::int32_t> merged_start_;  // per cell, −1 when the cell has no moving particle
  std::vector<std::int32_t> merged_count_;
  std::vector<std::int32_t> merged_items_;
  std::vector<float> merged_x_, merged_y_, merged_z_;
  std::vector<int> merged_cells_;  // the cells merged in the last step
  std::vector<char> is_active_;    // per particle, for Refresh
  // Per particle: 1 for boundary particles (their type never changes), read instead of the
  // type code in the position's w.
  std::vector<std::uint8_t> boundary_;
  // Per particle: its place in static_items_ (−1: not a binned boundary particle). ListActive's
  // marks are kept by that place, so that reading them in order gives the cell lists' order.
  std::vector<std::int32_t> static_rank_;
  std::vector<std::uint8_t> listed_;
};

}  // namespace owval::engine::internal
