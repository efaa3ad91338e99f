#pragma once
// Particle state shared by every solver and phase: one array per quantity, indexed by the
// configuration's row number (Sibernetic's "original" order). A scheme's own quantities (PCISPH's
// predicted positions, for one) live in its solver, not here.
#include <cstdint>
#include <vector>

#include "owval/engine/float4.hpp"

namespace owval::engine::internal {

inline bool IsBoundary(float type) { return static_cast<int>(type) == 3; }
inline bool IsLiquid(float type) { return static_cast<int>(type) == 1; }
inline bool IsElastic(float type) { return static_cast<int>(type) == 2; }
// Worm-body sub-types (2.05, 2.25) get full spring stiffness (sphFluid.cl:723-730); agar
// (2.25, 2.35).
inline bool IsWormBody(float type) { return type > 2.05f && type < 2.25f; }
inline bool IsAgar(float type) { return type > 2.25f && type < 2.35f; }

constexpr int kSlots = 32;  // neighbour slots per particle

struct Neighbour {
  std::int32_t index = -1;  // -1: empty slot (empty slots are at the end)
  float distance_m = -1;    // |x_i − x_j|·s from x(t)
};

struct ParticleState {
  std::vector<Float4> position;           // x(t) in cu; w = type code
  std::vector<Float4> velocity;           // m/s; boundary rows: inward wall normal (4 components)
  std::vector<Float4> acceleration;       // non-pressure acceleration a_i (m/s²)
  std::vector<Float4> last_acceleration;  // a used by the last integration (leapfrog)
  std::vector<float> density;             // kg/m³
  std::vector<float> pressure;            // Pa
  std::vector<Neighbour> neighbours;      // kSlots per particle
  // Per particle, bit n set when neighbour slot n holds a boundary particle: set with the lists
  // (NeighbourGrid::Refresh) for the particles it computes, so that the wall correction visits
  // only those slots.
  std::vector<std::uint32_t> boundary_slots;

  // Particles that move, and those the step must compute: moving ones plus the boundary
  // particles in their neighbour lists (boundary particles elsewhere affect nobody).
  std::vector<std::int32_t> moving;
  std::vector<std::int32_t> active;

  std::size_t size() const { return position.size(); }
  Neighbour* slots(std::size_t i) { return &neighbours[i * kSlots]; }
  const Neighbour* slots(std::size_t i) const { return &neighbours[i * kSlots]; }
  void Resize(std::size_t n) {
    position.resize(n);
    velocity.resize(n);
    acceleration.resize(n);
    last_acceleration.resize(n);
    density.assign(n, 0);
    pressure.assign(n, 0);
    neighbours.assign(n * kSlots, Neighbour{});
  }
};

}  // namespace owval::engine::internal
