#pragma once
// The split scheme's one-sided bond pass (Xpbd::ProjectBondsOneSided) for float, eight bonds per
// instruction: per bond b of particle i with partner j, from the positions the pass began with,
//   d = p_i − p_j, L = |d|, Δλ = (−(L − rest) − α̃·λ_b)/(1 + α̃), λ_b += Δλ, push_b = (Δλ/L)·d,
// skipped (λ_b kept, push_b = +0) when α̃ < 0 (no stiffness) or !(L > 0) [MMC16 eqs. 17-18];
// then p_i += Σ_b push_b over i's bonds in bond order.
//
// Layout: rows (a particle's bonds) are sorted by length and taken eight at a time, one row per
// lane; slot k of a group holds each lane's k-th bond (or nothing: α̃ = −1, push +0). A group's
// pushes are summed slot by slot in its lanes, so each row's sum is formed in bond order with
// the scalar loop's operations (no fused multiply-add), and +0 for an empty or skipped slot
// leaves a sum that starts at +0 unchanged: the scalar pass's floats, bit for bit. A group is
// one pass through registers: the points are loaded 16 bytes each and transposed (vector
// gathers and scalar loads through memory were slower on this machine's CPU).
//
//   [MMC16] M. Macklin, M. Müller, N. Chentanez. XPBD: position-based simulation of compliant
//           constrained dynamics. Motion in Games 2016.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "xpbd/projections.hpp"

namespace owval::engine::internal {

class BondLanes {
 public:
  struct Bond {
    std::int32_t particle, partner;
    float rest_cu;
  };
  // `bonds` in rows (each particle's bonds contiguous, in bond order): row r is
  // bonds[rows[r], rows[r + 1]), as Xpbd keeps them. The rows are cut into `parts` runs of
  // consecutive rows with equal shares of the bonds, and each run grouped on its own, so that
  // part t's groups [first_group(t), last_group(t)) move only the particles of its own rows
  // (threads that own a part each write their own stretch of memory). A row's floats do not
  // depend on its group.
  BondLanes(const std::vector<Bond>& bonds, const std::vector<std::size_t>& rows,
            std::size_t parts = 1);

  // Each bond's α̃ = α/h² by bond index (−1: no stiffness), for the step's substeps.
  void SetCompliance(const float* alpha_tilde);
  // One Jacobi pass: `start` holds the positions the pass began with, and one readable float
  // after its last particle (points are loaded 16 bytes at a time); each row's push is added to
  // correction[particle] (set to it on the first pass), the substep's sum of pushes unrounded by
  // p's ulp, and to p[particle] unless p is null (a substep's last pass: nothing reads it). The
  // first pass of a substep's solve reads λ = 0 for every bond (no reset needed); later passes read
  // the λ the previous one left (a pass that is both first and last stores none). Needs AVX2 and
  // FMA (UseAvx2() or UseAvx512()).
  void Pass(const Vec3<float>* start, Vec3<float>* p, Vec3<float>* correction, bool first) {
    Pass(start, p, correction, first, 0, groups());
  }
  // The same over groups [first_group, last_group) only. Groups move disjoint particles and
  // hold disjoint λ, so threads may pass disjoint ranges at once.
  void Pass(const Vec3<float>* start, Vec3<float>* p, Vec3<float>* correction, bool first,
            std::size_t first_group, std::size_t last_group);

  std::size_t groups() const { return group_slot_.size() - 1; }
  std::size_t parts() const { return part_group_.size() - 1; }
  std::size_t first_group(std::size_t part) const { return part_group_[part]; }
  std::size_t last_group(std::size_t part) const { return part_group_[part + 1]; }
  // Group g's lanes' particles (−1: an empty lane).
  const std::int32_t* lane_particles(std::size_t g) const { return &lane_particle_[g * kLanes]; }
  static constexpr int kLanes = 8;

 private:
  void AddGroups(const std::vector<Bond>& bonds, const std::vector<std::size_t>& row_first,
                 std::vector<std::size_t>* rows);

  std::vector<std::size_t> part_group_;            // part t's groups: [part_group_[t], [t + 1])
  std::vector<std::int32_t> slot_bond_;            // per slot: the bond, or −1
  std::vector<std::int32_t> slot_partner_offset_;  // per slot: 3 × the partner (or the row's
                                                   // particle if none), its x's float in p
  std::vector<std::int32_t> lane_particle_;        // per group lane: the row's particle, or −1
  std::vector<std::int32_t> lane_offset_;  // 3 × the lane's particle, −1 as 0 (a point to load)
  std::vector<std::size_t> group_slot_;    // group g's slots: [group_slot_[g], [g + 1])
  std::vector<float> rest_cu_, alpha_tilde_, lambda_;
};

// The bond substep's predict and velocity update (Xpbd::BondSubstep) over `values` contiguous
// floats (three per particle, for moving particles that are one block of the configuration), in
// the scalar loops' operations and order: v += h·a, p = x + (h·v)·to_cu (also written to
// `p_copy`, the bond pass's start). After the pass: v += (c·s)/h with c the pass's correction,
// then x advances by (h·v)·to_cu with its remainder r carried (y = (h·v)·to_cu + r,
// t = x + y, r = y − (t − x), x = p = t). Need AVX2 and FMA.
//
// The same as v = (p − x)·s/h, x = p in exact arithmetic, but in float p − x is a whole number
// of the position's ulps: with demo1's 55 substeps gravity moves a particle at rest by
// h²g/s = 0.05-0.2 ulp per substep and a bond at 3% strain corrects its particle by less than
// half an ulp at y = 44 cu, and both were rounded away on every substep (a quiet chain hung
// still; later, with the velocity kept, it sagged 2.8x too far: its springs' corrections were
// lost, gravity was not). The velocity now takes the corrections unrounded, and the position
// keeps what each substep's rounding dropped.
void PredictAvx2(std::size_t values, float h, float to_cu, const float* acceleration, float* v,
                 const float* x, float* p, float* p_copy);
void UpdateVelocityAvx2(std::size_t values, float h, float to_cu, float scale,
                        const float* correction, float* v, float* x, float* p, float* remainder);
// UpdateVelocityAvx2 then PredictAvx2 for the next substep in one sweep, each value's operations
// the two functions' in their order, without writing p (a substep with one pass reads only its
// start positions, `p_copy`; the substeps' last update writes p).
void UpdateAndPredictAvx2(std::size_t values, float h, float to_cu, float scale,
                          const float* correction, const float* acceleration, float* v, float* x,
                          float* remainder, float* p_copy);

}  // namespace owval::engine::internal
