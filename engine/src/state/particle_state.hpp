#pragma once
// Particle state shared by every solver phase: one array per quantity, indexed by the
// configuration's row number (Sibernetic's "original" order).
#include <cstdint>
#include <vector>

namespace owval::engine::internal {

struct Float4 {
  float x = 0, y = 0, z = 0, w = 0;
};

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
  std::vector<Float4> position;      // x(t) in cu; w = type code
  std::vector<Float4> velocity;      // m/s; boundary rows: inward wall normal (4 components)
  std::vector<Float4> predicted;     // x* during the pressure iterations (cu)
  std::vector<Float4> acceleration;  // non-pressure acceleration a_i (m/s²)
  std::vector<Float4> pressure_acceleration;
  std::vector<Float4> last_acceleration;  // a used by the last integration (leapfrog)
  std::vector<float> density, predicted_density, pressure;
  std::vector<Neighbour> neighbours;  // kSlots per particle

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
    predicted.resize(n);
    acceleration.resize(n);
    pressure_acceleration.resize(n);
    last_acceleration.resize(n);
    density.assign(n, 0);
    predicted_density.assign(n, 0);
    pressure.assign(n, 0);
    neighbours.assign(n * kSlots, Neighbour{});
  }
};

}  // namespace owval::engine::internal
