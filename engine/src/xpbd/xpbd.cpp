#include "xpbd/xpbd.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>
#include <type_traits>

#include "kernels/kernels.hpp"
#include "kernels/simd.hpp"
#include "neighbours/reciprocal_pairs.hpp"
#include "owval/base/errors.hpp"
#include "phases/density.hpp"
#include "phases/forces.hpp"
#include "phases/membranes.hpp"
#include "phases/pressure_force.hpp"
#include "phases/walls.hpp"
#include "state/initial_state.hpp"
#include "state/non_finite.hpp"
#include "state/state_io.hpp"
#include "xpbd/bond_pushes.hpp"
#include "xpbd/density_lanes.hpp"

namespace owval::engine::internal {
namespace {

// Sibernetic's forces with the switched-off ones' coefficients zeroed: the shared phase then
// adds exactly zero for them.
SphConstants ForceConstants(const SphConstants& k, const PhysicsConstants::Xpbd& p) {
  SphConstants forces = k;
  if (!p.viscosity) forces.mass_lap_wviscosity = 0;
  if (!p.surface_tension) forces.surface_tension = 0;
  return forces;
}

// (b − a)×(c − a)·(x − a) for the triangle's corners a, b, c in `position`: its sign is the side
// of the triangle's plane x is on (0 on it, or a degenerate triangle). In double: the side test
// at 50-90 cu.
double SideOf(const Float4& x, const std::array<int, 3>& triangle,
              std::span<const Float4> position) {
  const Float4 &a = position[triangle[0]], &b = position[triangle[1]], &c = position[triangle[2]];
  return SideOfPlane<double>({double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z},
                             {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z},
                             {double(x.x) - a.x, double(x.y) - a.y, double(x.z) - a.z});
}

// Whether x lies over the triangle's side of its edge u–v: its offset from u, along the
// triangle's own direction away from the edge (the third corner's offset with its part along
// the edge removed), is positive.
bool OverTriangleSideOfEdge(const Float4& x, const std::array<int, 3>& triangle, int u, int v,
                            std::span<const Float4> position) {
  const int w = triangle[0] != u && triangle[0] != v   ? triangle[0]
                : triangle[1] != u && triangle[1] != v ? triangle[1]
                                                       : triangle[2];
  const Float4 &pu = position[u], &pv = position[v], &pw = position[w];
  const double e[3] = {double(pv.x) - pu.x, double(pv.y) - pu.y, double(pv.z) - pu.z};
  const double f[3] = {double(pw.x) - pu.x, double(pw.y) - pu.y, double(pw.z) - pu.z};
  const double g[3] = {double(x.x) - pu.x, double(x.y) - pu.y, double(x.z) - pu.z};
  const double along =
      (f[0] * e[0] + f[1] * e[1] + f[2] * e[2]) / (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  double over = 0;
  for (int a = 0; a < 3; ++a) over += (f[a] - along * e[a]) * g[a];
  return over > 0;
}

// |a − b|² (cu²), in double.
double Norm2(const Float4& a, const Float4& b) {
  const double d[3] = {double(a.x) - b.x, double(a.y) - b.y, double(a.z) - b.z};
  return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

// The distance from x to the segment u–v (cu).
double DistanceToSegment(const Float4& x, const Float4& u, const Float4& v) {
  const Vec3<double> q{x.x, x.y, x.z}, a{u.x, u.y, u.z}, b{v.x, v.y, v.z};
  const double t = std::clamp(EdgeParameterOf(q, a, b), 0.0, 1.0);
  return Norm(Vec3<double>{q[0] - a[0] - t * (b[0] - a[0]), q[1] - a[1] - t * (b[1] - a[1]),
                           q[2] - a[2] - t * (b[2] - a[2])});
}

}  // namespace

double SiberneticTargetDensityOf(const PhysicsConstants& constants) {
  // The floats every phase uses (SphConstants); W(0) = 315/(64π h³) in cu⁻³.
  const SphConstants k = SphConstants::From(constants);
  const double s = k.scale;
  return double(k.rest_density) + double(k.mass_kg) / (s * s * s) * Wpoly6(double(k.h_cu), 0.0);
}

int SubstepsOf(const SiberneticConfig& config, const PhysicsConstants& constants) {
  const PhysicsConstants::Xpbd& p = constants.xpbd;
  if (p.substeps > 0) return p.substeps;
  double k_max = 0;
  // elastic_count() counts the configuration's particles: once, not once per elastic particle
  // (demo1's 17,841 particles × 218 elastic ones cost 90 M instructions of a 0.01 s run).
  const std::size_t elastic = config.elastic_count();
  for (std::size_t e = 0; e < elastic; ++e)
    for (int slot = 0; slot < kSpringSlots; ++slot) {
      const Row4& c = config.connection[e * kSpringSlots + slot];
      if (c[0] < 0) break;
      const bool body = IsWormBody(config.position[e][3]) &&
                        IsWormBody(config.position[static_cast<std::size_t>(c[0])][3]);
      k_max = std::max(k_max, constants.elasticity_coefficient *
                                  (body ? 1.0 : constants.non_worm_body_spring_factor));
    }
  const double omega_dt = std::sqrt(k_max) * double(float(constants.time_step_s));
  const double n = std::ceil(std::numbers::pi * omega_dt / p.damping_budget);
  return static_cast<int>(std::clamp(n, 4.0, 1000.0));
}

double DensityComplianceOf(const SiberneticConfig& config, const PhysicsConstants& constants) {
  if (constants.xpbd.density_compliance > 0) return constants.xpbd.density_compliance;
  const auto& g = constants.gravity;
  const double g_abs = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  bool liquid = false;
  for (const Row4& p : config.position) liquid = liquid || IsLiquid(p[3]);
  double top = config.box.ymin;
  for (const Row4& p : config.position)
    if (liquid ? IsLiquid(p[3]) : !IsBoundary(p[3])) top = std::max(top, double(p[1]));
  const double s = double(float(constants.simulation_scale));
  const double height_m = std::max(top - config.box.ymin, constants.h_cu) * s;
  const double c = 10 * std::sqrt(2 * g_abs * height_m);
  return c > 0 ? (s / c) * (s / c) : 0.0;
}

template <typename T>
Xpbd<T>::Xpbd(const SiberneticConfig& config, const PhysicsConstants& constants, int threads)
    : k_(SphConstants::From(constants)),
      k_forces_(ForceConstants(k_, constants.xpbd)),
      parameters_(constants.xpbd),
      delta_(float(constants.delta)),
      threads_(threads),
      substeps_(SubstepsOf(config, constants)),
      box_(config.box),
      grid_(config.box, k_),
      matter_(ElasticMatterOf(config, k_)) {
  // Measured: the unsplit scheme turns each substep's membrane correction into velocity with no
  // contact velocity pass to damp it, and demo1 spans the box by step 10 (docs/xpbd.md).
  if (parameters_.membranes && parameters_.density_passes == 0)
    throw InputError(
        "--set xpbd_membranes=1: needs the split scheme (xpbd_density_passes >= 1); the unsplit "
        "scheme has no contact velocity pass for membrane contacts");
  LoadParticles(config, &state_);
  grid_.SetStatic(state_);
  const std::size_t n = state_.size();
  moving_.assign(n, 0);
  for (std::int32_t i : state_.moving) moving_[i] = -1;
  parallel_ = threads_ > 1 &&
              state_.moving.size() >= (parameters_.density_passes > 0 ? kParallelMoversPerStep
                                                                      : kParallelMoversPerSubstep);
  x_.resize(n);
  v_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Float4 &x = state_.position[i], &v = state_.velocity[i];
    x_[i] = {T(x.x), T(x.y), T(x.z)};
    v_[i] = moving_[i] ? Vec3<T>{T(v.x), T(v.y), T(v.z)} : Vec3<T>{0, 0, 0};
  }
  p_ = x_;
  dp_.assign(n, {0, 0, 0});
  bond_start_ = p_;
  bond_start_.push_back({0, 0, 0});  // BondLanes::Pass loads 16 bytes per point
  bond_correction_.assign(n, {0, 0, 0});
  position_remainder_.assign(n, {0, 0, 0});
  wall_normal_.assign(n, {0, 0, 0});
  wall_friction_ = std::pow(
      0.99, 1.0 / (parameters_.density_passes > 0 ? parameters_.density_passes : substeps_));
  density_lambda_.assign(n, 0);
  density_dlambda_.assign(n, 0);
  pressure_acceleration_.assign(n, Float4{});
  for (std::size_t e = 0; e < matter_.particle_count; ++e) {
    for (int slot = 0; slot < kSpringSlots; ++slot) {
      const Row4& c = config.connection[e * kSpringSlots + slot];
      if (c[0] < 0) break;
      const std::int32_t j = static_cast<std::int32_t>(c[0]);
      const bool body = IsWormBody(config.position[e][3]) && IsWormBody(config.position[j][3]);
      const double k =
          constants.elasticity_coefficient * (body ? 1.0 : constants.non_worm_body_spring_factor);
      bonds_.push_back({std::int32_t(e), j, T(c[1]), T(k), static_cast<int>(c[2])});
    }
  }
  bond_lambda_.assign(bonds_.size(), 0);
  for (std::size_t b = 0; b < bonds_.size(); ++b)  // rows: each particle's bonds, contiguous
    if (b == 0 || bonds_[b].particle != bonds_[b - 1].particle) bond_rows_.push_back(b);
  bond_rows_.push_back(bonds_.size());
  moving_block_ =
      !state_.moving.empty() &&
      std::size_t(state_.moving.back() - state_.moving.front()) + 1 == state_.moving.size();
  if constexpr (std::is_same_v<T, float>) {
    if (UseAvx2() || UseAvx512()) {
      std::vector<BondLanes::Bond> lanes;
      for (const Bond& bond : bonds_) lanes.push_back({bond.particle, bond.partner, bond.rest_cu});
      // Rows for each thread to own when the substeps can be shared (ShareBondSubsteps): the
      // float lanes, one pass per substep, the split scheme, and at least kRowsPerThread rows a
      // thread. Sharing costs a barrier per substep. The worm's 1,300 rows a thread repay it
      // (0.25 s of bond substeps per 200 steps against 0.44 on one thread); demo1's 171 do not
      // (1.51 s against 1.46-1.57 per 10,000 steps in process), and as a whole process, where the
      // trajectory writers' threads take a core from time to time, a thread preempted at a barrier
      // stalls the other: demo1 took 7.0 s on two threads shared, 4.8 s serial
      // (docs/benchmarks.md, "Bond substeps shared only when a thread's share repays a barrier").
      constexpr std::size_t kRowsPerThread = 512;
      const bool shared = threads_ > 1 && moving_block_ && parameters_.iterations == 1 &&
                          parameters_.density_passes > 0 &&
                          bond_rows_.size() > kRowsPerThread * std::size_t(threads_);
      bond_lanes_.emplace(lanes, bond_rows_, shared ? std::size_t(threads_) : 1);
    }
  }
  ShareBondSubsteps();
  RefreshLists();
  const double h = k_.h_cu, s = k_.scale;  // the float values every phase uses
  rest_density_ = parameters_.rest_density > 0 ? parameters_.rest_density : DerivedRestDensity();
  sibernetic_target_density_ = SiberneticTargetDensityOf(constants);
  density_compliance_ = DensityComplianceOf(config, constants);
  kernel_ = {T(h), T(h * h), T(constants.mass_kg / (rest_density_ * s * s * s)),
             T(Wpoly6Coefficient(h)), T(SpikyGradientCoefficient(h))};
  if (parameters_.tensile_correction > 0) {
    const T dq = T(parameters_.tensile_distance_h * h);
    tensile_ = {T(parameters_.tensile_correction * h * h), T(1) / kernel_.W(dq * dq),
                parameters_.tensile_exponent};
    tensile_dp_.assign(n, {0, 0, 0});
  }
}

// The step's neighbour lists from x(t); with xpbd_reciprocal_lists, only pairs listed both ways
// (neighbours/reciprocal_pairs.hpp), so that every pair term has its reaction.
template <typename T>
void Xpbd<T>::RefreshLists() {
  grid_.Refresh(&state_, threads_);
  if (parameters_.reciprocal_lists) KeepReciprocalPairs(&state_);
}

// The mean initial density, m/s³·(W(0) + ΣW) with the constraint's own kernel and lists, of the
// liquid particles with at least 20 listed neighbours (the interior); Sibernetic's ρ0 when the
// configuration has no such liquid.
template <typename T>
double Xpbd<T>::DerivedRestDensity() const {
  const double h = k_.h_cu, poly6 = Wpoly6Coefficient(h), s = k_.scale;
  double sum = 0;
  int count = 0;
  for (std::int32_t i : state_.moving) {
    if (!IsLiquid(state_.position[i].w)) continue;
    const Neighbour* slots = state_.slots(i);
    int listed = 0;
    double w = poly6 * h * h * h * h * h * h;  // W(0)
    for (; listed < kSlots && slots[listed].index >= 0; ++listed) {
      const Float4 &a = state_.position[i], &b = state_.position[slots[listed].index];
      const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
      const double q = h * h - (dx * dx + dy * dy + dz * dz);
      if (q > 0) w += poly6 * q * q * q;
    }
    if (listed < 20) continue;
    sum += k_.mass_kg / (s * s * s) * w;
    ++count;
  }
  return count > 0 ? sum / count : double(k_.rest_density);
}

template <typename T>
void Xpbd<T>::Step() {
  const bool first = step_ == 0;
  clock_.Start();
  RefreshLists();
  clock_.Mark(kNeighbours);
  ComputeDensity(k_, &state_, threads_);
  clock_.Mark(kDensity);
  if (parameters_.membranes && !first) {
    FindMembraneContacts();
    clock_.Mark(kMembranes);
  }
  if (!first) {
    ComputeForces();  // at x(t), held over the substeps
    HoldAcceleration();
    clock_.Mark(kForces);
    const int m = parameters_.density_passes;
    if (m <= 0) {
      const T h = T(k_.time_step_s) / T(substeps_);
      for (int substep = 0; substep < substeps_; ++substep) Substep(h);
      clock_.Mark(kSubsteps);
    } else {
      const int inner = (substeps_ + m - 1) / m;  // at least the derived n bond substeps
      const T H = T(k_.time_step_s) / T(m), h = H / T(inner);
      BondComplianceOf(h);
      for (int pass = 0; pass < m; ++pass) {
        if (bond_shares_.empty()) {
          if (!BondSubstepsInLanes(h, inner))
            for (int substep = 0; substep < inner; ++substep) BondSubstep(h);
        } else {
          SharedBondSubsteps(h, inner);
        }
        clock_.Mark(kBondSubsteps);
        Correct(H);
        clock_.Mark(kCorrections);
      }
    }
  }
  if (!parameters_.membranes) {
    InteractWithMembranes();
    clock_.Mark(kMembranes);
  }
  ++step_;
}

// One substep of h [M19 Alg. 1]: the multipliers restart at zero, K passes, velocities from
// the positions' change.
template <typename T>
void Xpbd<T>::Substep(T h) {
  for (std::int32_t i : state_.moving) {  // only moving particles' λ are read
    wall_normal_[i] = {0, 0, 0};
    density_lambda_[i] = 0;
  }
  Predict(h);
  std::fill(bond_lambda_.begin(), bond_lambda_.end(), T(0));
  for (int pass = 0; pass < parameters_.iterations; ++pass) {
    ProjectDensity(h);
    ProjectBonds(h);
    ProjectMembranes();
    ProjectBoundaries();
  }
  UpdateVelocities(h);
}

// A bond substep of the split scheme [M19 Alg. 1 without the density and wall constraints],
// on one thread: a few microseconds of work, for which a parallel region per substep cost more
// than it saved on a shared machine. SharedBondSubsteps runs a step's substeps in one region.
template <typename T>
void Xpbd<T>::BondSubstep(T h) {
  const T to_cu = T(1) / T(k_.scale), scale = T(k_.scale);
  const bool predicted_in_lanes = BondSubstepInLanes(h, to_cu, scale, true);
  if (!predicted_in_lanes) {
    for (std::size_t n = 0; n < state_.moving.size(); ++n) {
      const std::int32_t i = state_.moving[n];
      for (int d = 0; d < 3; ++d) {
        v_[i][d] += h * held_acceleration_[n][d];
        p_[i][d] = x_[i][d] + h * v_[i][d] * to_cu;
      }
    }
  }
  for (int pass = 0; pass < parameters_.iterations; ++pass)
    ProjectBondsOneSided(pass == 0, pass == 0 && predicted_in_lanes,
                         pass + 1 == parameters_.iterations);
  if (BondSubstepInLanes(h, to_cu, scale, false)) return;
  for (std::int32_t i : state_.moving) {
    for (int a = 0; a < 3; ++a) {  // UpdateVelocityAvx2's operations (bond_pushes.hpp: why)
      v_[i][a] = v_[i][a] + bond_correction_[i][a] * scale / h;
      const T move = h * v_[i][a] * to_cu + position_remainder_[i][a];
      const T position = x_[i][a] + move;
      position_remainder_[i][a] = move - (position - x_[i][a]);
      x_[i][a] = p_[i][a] = position;
    }
  }
}

// One share of the bond substeps per part of the bond lanes (their constructor cut the rows
// for the threads): its groups and the moving particles from its first row's particle to the
// next part's, bondless ones included, so that each thread writes its own stretch of memory.
template <typename T>
void Xpbd<T>::ShareBondSubsteps() {
  if (!bond_lanes_ || bond_lanes_->parts() < 2) return;
  const BondLanes& lanes = *bond_lanes_;
  std::vector<std::int32_t> begin;  // each part's first particle
  for (std::size_t t = 0; t < lanes.parts(); ++t) {
    std::int32_t first = std::numeric_limits<std::int32_t>::max();
    for (std::size_t g = lanes.first_group(t); g < lanes.last_group(t); ++g)
      for (int l = 0; l < BondLanes::kLanes; ++l)
        if (const std::int32_t i = lanes.lane_particles(g)[l]; i >= 0) first = std::min(first, i);
    if (lanes.first_group(t) == lanes.last_group(t)) return;  // a part without rows: serial
    begin.push_back(t == 0 ? state_.moving.front() : first);
  }
  begin.push_back(state_.moving.back() + 1);
  bond_shares_.resize(lanes.parts());
  for (std::size_t t = 0; t < lanes.parts(); ++t) {
    BondShare& share = bond_shares_[t];
    share.first_group = lanes.first_group(t);
    share.last_group = lanes.last_group(t);
    share.first_particle = begin[t];
    share.end_particle = begin[t + 1];
  }
  bond_start_next_ = bond_start_;
}

// The split scheme's bond substeps as BondSubstep computes them, each thread predicting,
// passing and updating its own share in the same vector lanes: the same floats, bit for bit.
// One barrier per substep, between the predictions and the pass that reads them: each pass
// reads only its substep's start positions, which alternate between two buffers, so a thread
// may predict the next substep while another still passes this one.
template <typename T>
void Xpbd<T>::SharedBondSubsteps(T h, int substeps) {
  if constexpr (std::is_same_v<T, float>) {
    const float to_cu = 1.0f / float(k_.scale), scale = float(k_.scale);
    const std::int32_t first = state_.moving.front();  // held_acceleration_'s index is i − first
    Vec3<float>* starts[2] = {bond_start_.data(), bond_start_next_.data()};
#pragma omp parallel num_threads(threads_)
    {
      const std::size_t team = std::size_t(omp_get_num_threads());
      const std::size_t thread = std::size_t(omp_get_thread_num());
      for (int substep = 0; substep < substeps; ++substep) {
        Vec3<float>* start = starts[substep % 2];
        for (std::size_t t = thread; t < bond_shares_.size(); t += team) {
          const BondShare& share = bond_shares_[t];
          const std::int32_t i = share.first_particle;
          PredictAvx2(3 * std::size_t(share.end_particle - i), h, to_cu,
                      held_acceleration_[std::size_t(i - first)].data(), v_[i].data(), x_[i].data(),
                      p_[i].data(), start[i].data());
        }
#pragma omp barrier
        for (std::size_t t = thread; t < bond_shares_.size(); t += team) {
          const BondShare& share = bond_shares_[t];
          const std::int32_t i = share.first_particle;
          bond_lanes_->Pass(start, nullptr, bond_correction_.data(), true, share.first_group,
                            share.last_group);
          UpdateVelocityAvx2(3 * std::size_t(share.end_particle - i), h, to_cu, scale,
                             bond_correction_[i].data(), v_[i].data(), x_[i].data(), p_[i].data(),
                             position_remainder_[i].data());
        }
      }
    }
  } else {
    for (int substep = 0; substep < substeps; ++substep) BondSubstep(h);
  }
}

// BondSubstep's predict (or velocity update) in vector lanes, when the float solver has them and
// the moving particles are one block (bond_pushes.hpp); false otherwise.
template <typename T>
bool Xpbd<T>::BondSubstepInLanes(T h, T to_cu, T scale, bool predict) {
  if constexpr (!std::is_same_v<T, float>) {
    return false;
  } else {
    static_assert(sizeof(Vec3<float>) == 3 * sizeof(float), "Vec3 arrays are flat floats");
    if (!bond_lanes_ || !moving_block_) return false;
    const std::size_t first = std::size_t(state_.moving.front()), values = 3 * state_.moving.size();
    float *v = v_[first].data(), *x = x_[first].data(), *p = p_[first].data();
    if (predict)
      PredictAvx2(values, h, to_cu, held_acceleration_.front().data(), v, x, p,
                  bond_start_[first].data());
    else
      UpdateVelocityAvx2(values, h, to_cu, scale, bond_correction_[first].data(), v, x, p,
                         position_remainder_[first].data());
    return true;
  }
}

// The split scheme's `substeps` bond substeps of h as BondSubstep computes them in lanes, when
// the float solver has them, the moving particles are one block and a substep has one pass (the
// default): each substep's velocity update and the next one's prediction in one sweep of the
// particles (UpdateAndPredictAvx2: the same operations on each value), and p written by the
// last update only (a one-pass substep reads its start positions, never p). False otherwise.
template <typename T>
bool Xpbd<T>::BondSubstepsInLanes(T h, int substeps) {
  if constexpr (!std::is_same_v<T, float>) {
    return false;
  } else {
    if (!bond_lanes_ || !moving_block_ || parameters_.iterations != 1 || substeps < 1) return false;
    const float to_cu = 1.0f / float(k_.scale), scale = float(k_.scale);
    const std::size_t first = std::size_t(state_.moving.front()), values = 3 * state_.moving.size();
    float *v = v_[first].data(), *x = x_[first].data(), *p = p_[first].data();
    float *start = bond_start_[first].data(), *remainder = position_remainder_[first].data();
    const float *acceleration = held_acceleration_.front().data(),
                *correction = bond_correction_[first].data();
    PredictAvx2(values, h, to_cu, acceleration, v, x, p, start);
    for (int substep = 0; substep < substeps; ++substep) {
      bond_lanes_->Pass(bond_start_.data(), nullptr, bond_correction_.data(), true);
      if (substep + 1 < substeps)
        UpdateAndPredictAvx2(values, h, to_cu, scale, correction, acceleration, v, x, remainder,
                             start);
      else
        UpdateVelocityAvx2(values, h, to_cu, scale, correction, v, x, p, remainder);
    }
    return true;
  }
}

// The split scheme's correction over H = dt/m: the density constraints (compliance α/H², as
// PBF projects them once per step [MM13]) and the walls on the bond substeps' positions, the
// correction's displacement added to the velocity as Δp·s/H, then the contact velocity pass.
template <typename T>
void Xpbd<T>::Correct(T H) {
  for (std::int32_t i : state_.moving) {  // only moving particles' λ are read
    wall_normal_[i] = {0, 0, 0};
    density_lambda_[i] = 0;
  }
  for (int pass = 0; pass < parameters_.iterations; ++pass) {
    ProjectDensity(H);
    ProjectMembranes();
    ProjectBoundaries();
  }
  const T scale = T(k_.scale);
  const T floor = T(box_.ymin) + T(k_.r0_cu), restitution = T(parameters_.floor_restitution);
  for (std::int32_t i : state_.moving) {
    const Vec3<T> predicted = v_[i];
    for (int a = 0; a < 3; ++a) v_[i][a] += (p_[i][a] - x_[i][a]) * scale / H;
    WallVelocity(i, predicted, restitution);
    if (p_[i][1] <= floor && v_[i][1] < 0) v_[i][1] = -restitution * v_[i][1];
    x_[i] = p_[i];
    WriteFloatState(i);
  }
}

template <typename T>
void Xpbd<T>::WriteFloatState(std::int32_t i) {
  Float4& x = state_.position[i];
  Float4& v = state_.velocity[i];
  x = {float(x_[i][0]), float(x_[i][1]), float(x_[i][2]), x.w};
  v = {float(v_[i][0]), float(v_[i][1]), float(v_[i][2]), v.w};
}

// Each moving particle's acceleration over the step's substeps, a + a_pressure in T (moving
// order), added once per step instead of once per substep.
template <typename T>
void Xpbd<T>::HoldAcceleration() {
  held_acceleration_.resize(state_.moving.size());
  for (std::size_t n = 0; n < state_.moving.size(); ++n) {
    const std::int32_t i = state_.moving[n];
    const Float4 &a = state_.acceleration[i], &ap = pressure_acceleration_[i];
    held_acceleration_[n] = {T(a.x) + T(ap.x), T(a.y) + T(ap.y), T(a.z) + T(ap.z)};
  }
}

template <typename T>
void Xpbd<T>::ComputeForces() {
  ComputeViscosityGravitySurfaceTension(k_forces_, &state_, threads_);
  if (!parameters_.pressure_force) return;
  // One equation-of-state pass with PCISPH's δ: p = max(0, δ(ρ − ρ0)).
  for (std::int32_t i : state_.active)
    state_.pressure[i] = std::max(0.0f, delta_ * (state_.density[i] - k_.rest_density));
  ComputePressureAcceleration(k_, state_, state_.density, k_.rest_density * delta_,
                              &pressure_acceleration_, threads_);
}

template <typename T>
void Xpbd<T>::Predict(T dt) {
  const T to_cu = T(1) / T(k_.scale);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::size_t n = 0; n < state_.moving.size(); ++n) {
    const std::int32_t i = state_.moving[n];
    for (int d = 0; d < 3; ++d) {
      v_[i][d] += dt * held_acceleration_[n][d];
      p_[i][d] = x_[i][d] + dt * v_[i][d] * to_cu;
    }
  }
}

// Jacobi over the particles [MM13 eqs. 9-12] with XPBD's compliance: every Δλ_i from the same
// positions, then Δp_i = Σ_j (Δλ_i + Δλ_j)·V0∇W(p_i − p_j), a fixed neighbour counting only its
// own constraint's share. The second loop reuses the first's per-slot gradients (the positions
// do not move between them), so each pair's square root and division are taken once. With
// xpbd_tensile_correction every listed pair adds s_corr·V0∇W [MM13 eq. 14] (a fixed neighbour
// too: it is a pair term, not a multiplier), summed in the first loop and added after the Δλ
// terms.
template <typename T>
void Xpbd<T>::ProjectDensity(T dt) {
  const T alpha_tilde = T(density_compliance_) / (dt * dt);
  if constexpr (std::is_same_v<T, float>) {
    // The lanes do not know the particles' kinds: the push-only body pairs take the scalar loops.
    if (bond_lanes_ && !parameters_.body_push_only) return ProjectDensityInLanes(alpha_tilde);
  }
  const std::vector<std::int32_t>& moving = state_.moving;
  slot_gradient_.resize(moving.size() * kSlots);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::size_t n = 0; n < moving.size(); ++n) {
    const std::int32_t i = moving[n];
    const Neighbour* slots = state_.slots(i);
    Vec3<T>* gradient = &slot_gradient_[n * kSlots];
    T w = kernel_.W(0);
    Vec3<T> gradient_i{0, 0, 0}, tensile{0, 0, 0};
    T norm2 = 0;
    for (int m = 0; m < kSlots && slots[m].index >= 0; ++m) {
      const std::int32_t j = slots[m].index;
      const Vec3<T> d{p_[i][0] - p_[j][0], p_[i][1] - p_[j][1], p_[i][2] - p_[j][2]};
      const T wj = kernel_.W(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      w += wj;
      const Vec3<T> g = kernel_.Gradient(d);
      gradient[m] = g;
      for (int a = 0; a < 3; ++a) gradient_i[a] += g[a];
      if (moving_[j]) norm2 += g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
      if (tensile_.on()) {
        const T s_corr = tensile_.Of(wj);
        for (int a = 0; a < 3; ++a) tensile[a] += s_corr * g[a];
      }
    }
    norm2 += gradient_i[0] * gradient_i[0] + gradient_i[1] * gradient_i[1] +
             gradient_i[2] * gradient_i[2];
    UpdateDensityLambda(i, w, norm2, alpha_tilde);
    if (tensile_.on()) tensile_dp_[i] = tensile;
  }
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::size_t n = 0; n < moving.size(); ++n) {
    const std::int32_t i = moving[n];
    const Neighbour* slots = state_.slots(i);
    const Vec3<T>* gradient = &slot_gradient_[n * kSlots];
    Vec3<T> dp{0, 0, 0};
    for (int m = 0; m < kSlots && slots[m].index >= 0; ++m) {
      const std::int32_t j = slots[m].index;
      const T lambda = PairMultiplier(i, j);
      for (int a = 0; a < 3; ++a) dp[a] += lambda * gradient[m][a];
    }
    if (tensile_.on())
      for (int a = 0; a < 3; ++a) dp[a] += tensile_dp_[i][a];
    dp_[i] = dp;
  }
  for (std::int32_t i : moving)
    for (int a = 0; a < 3; ++a) p_[i][a] += dp_[i][a];
}

// The pair's Δλ_i + Δλ_j in Δp_i = Σ_j (Δλ_i + Δλ_j)·V0∇W (a fixed j counts only i's share).
// With xpbd_body_push_only, in a pair of a liquid and an elastic particle the elastic one's Δλ
// counts only when it pushes (≤ 0), in both particles' sums, so the pair stays equal and
// opposite: demo1's elastic layer is under-dense (78% of its particle-steps, C < 0 from the
// missing neighbours outside) and its two-sided constraint pulled the liquid into the
// membranes (docs/xpbd.md, item 10). The liquid's own constraint keeps both directions.
template <typename T>
T Xpbd<T>::PairMultiplier(std::int32_t i, std::int32_t j) const {
  if (!moving_[j]) return density_dlambda_[i];
  T own = density_dlambda_[i], other = density_dlambda_[j];
  if (parameters_.body_push_only) {
    const float type_i = state_.position[i].w, type_j = state_.position[j].w;
    if (IsLiquid(type_i) && IsElastic(type_j)) other = std::min(other, T(0));
    if (IsElastic(type_i) && IsLiquid(type_j)) own = std::min(own, T(0));
  }
  return own + other;
}

// Δλ_i from the constraint's sum w = W(0) + Σ_j W and norm2 = Σ_k |∇_k C_i|².
template <typename T>
void Xpbd<T>::UpdateDensityLambda(std::int32_t i, T w, T norm2, T alpha_tilde) {
  const T c = kernel_.rest_volume * w - 1;  // both directions: C < 0 pulls neighbours in
  const T denominator = norm2 + alpha_tilde;
  const T dlambda = denominator > 0 ? (-c - alpha_tilde * density_lambda_[i]) / denominator : T(0);
  density_dlambda_[i] = dlambda;
  density_lambda_[i] += dlambda;
}

// ProjectDensity for the float solver in 8-lane groups of moving particles (density_lanes.hpp):
// the same floats. A short last group repeats its last particle in the spare lanes and drops
// their results.
template <typename T>
void Xpbd<T>::ProjectDensityInLanes(T alpha_tilde) {
  if constexpr (std::is_same_v<T, float>) {
    const std::vector<std::int32_t>& moving = state_.moving;
    const std::size_t groups = (moving.size() + 7) / 8, per_group = std::size_t(kSlots) * kRecord;
    lane_record_.resize(groups * per_group);
    lane_slots_.resize(groups);
    const std::int32_t last = std::int32_t(p_.size()) - 1;
    const float last_point[4] = {p_[last][0], p_[last][1], p_[last][2], 0.0f};
    DensityLanes in{p_[0].data(),   last,    last_point, state_.neighbours.data(),
                    moving_.data(), kernel_, tensile_};
    if (moving_block_) in.moving_first = moving.front(), in.moving_end = moving.back() + 1;
    const auto lanes_of = [&](std::size_t g, std::int32_t particle[8]) {
      const std::size_t lanes = std::min<std::size_t>(8, moving.size() - 8 * g);
      for (std::size_t l = 0; l < 8; ++l) particle[l] = moving[8 * g + std::min(l, lanes - 1)];
      return lanes;
    };
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
    for (std::size_t g = 0; g < groups; ++g) {
      std::int32_t particle[8];
      const std::size_t lanes = lanes_of(g, particle);
      float w[8], norm2[8], tensile[3][8];
      lane_slots_[g] =
          DensityConstraintAvx2(in, particle, w, norm2, &lane_record_[g * per_group], tensile);
      for (std::size_t l = 0; l < lanes; ++l) {
        UpdateDensityLambda(particle[l], w[l], norm2[l], alpha_tilde);
        if (tensile_.on()) tensile_dp_[particle[l]] = {tensile[0][l], tensile[1][l], tensile[2][l]};
      }
    }
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
    for (std::size_t g = 0; g < groups; ++g) {
      std::int32_t particle[8];
      const std::size_t lanes = lanes_of(g, particle);
      float dp[3][8];
      DensityDisplacementAvx2(particle, density_dlambda_.data(), &lane_record_[g * per_group],
                              lane_slots_[g], dp);
      for (std::size_t l = 0; l < lanes; ++l) {
        dp_[particle[l]] = {dp[0][l], dp[1][l], dp[2][l]};
        if (tensile_.on())
          for (int a = 0; a < 3; ++a) dp_[particle[l]][a] += tensile_dp_[particle[l]][a];
      }
    }
    for (std::int32_t i : moving)
      for (int a = 0; a < 3; ++a) p_[i][a] += dp_[i][a];
  }
}

// A bond's stiffness now: a muscle's is k·(1 + activation·strength).
template <typename T>
T Xpbd<T>::StiffnessOf(const Bond& bond) const {
  T k = bond.stiffness;
  if (bond.muscle >= 1 && bond.muscle <= kMuscles) {
    const float activation = matter_.muscle_activation[bond.muscle - 1];
    if (activation > 0) k *= T(1) + T(activation) * T(parameters_.muscle_strength);
  }
  return k;
}

// Gauss-Seidel over the bonds in file order; a bond moves only its own row's particle, as
// Sibernetic's spring force acts only on it (pairs listed both ways move both).
template <typename T>
void Xpbd<T>::ProjectBonds(T dt) {
  for (std::size_t b = 0; b < bonds_.size(); ++b) {
    const Bond& bond = bonds_[b];
    const T k = StiffnessOf(bond);
    if (!(k > 0)) continue;
    const T alpha_tilde = T(parameters_.bond_compliance_scale) / (k * dt * dt);
    Vec3<T> partner = p_[bond.partner];
    ProjectDistance(&p_[bond.particle], &partner, T(1), T(0), bond.rest_cu, alpha_tilde,
                    &bond_lambda_[b]);
  }
}

// Each bond's α̃ = scale/(k(t)·h²) for the step's substep h (the activations hold over a step),
// or −1 for a bond without stiffness, as ProjectBonds computes them per bond and substep.
template <typename T>
void Xpbd<T>::BondComplianceOf(T dt) {
  // The same h and activations give the same α̃ (an activation only acts when > 0, and ±0 are
  // equal): demo1's 1,848 bonds cost 19 M instructions per 500 steps recomputed every step.
  if (dt == compliance_h_ && matter_.muscle_activation == compliance_activation_) return;
  compliance_h_ = dt;
  compliance_activation_ = matter_.muscle_activation;
  bond_alpha_tilde_.resize(bonds_.size());
  for (std::size_t b = 0; b < bonds_.size(); ++b) {
    const Bond& bond = bonds_[b];
    const T k = StiffnessOf(bond);
    bond_alpha_tilde_[b] = k > 0 ? T(parameters_.bond_compliance_scale) / (k * dt * dt) : T(-1);
  }
  if constexpr (std::is_same_v<T, float>)
    if (bond_lanes_) bond_lanes_->SetCompliance(bond_alpha_tilde_.data());
}

// The split scheme's bond pass: ProjectBonds with the step's α̃, Jacobi. Every bond of a row
// reads both ends as the pass began and the row's particle moves by the sum of its bonds'
// corrections (w = 1 for the row's particle, 0 for the partner, as ProjectDistance with those
// weights). Per substep α̃ = 1/(k h²) is large (demo1: k h² = 3.8e-5, α̃ ≈ 2.6e4), so each bond
// moves its particle by ~1/α̃ of its error and the sum cannot overshoot; Gauss-Seidel's serial
// chain (a square root and a division per bond, through the particle's position) cost 5x more.
template <typename T>
void Xpbd<T>::ProjectBondsOneSided(bool first_pass, bool start_written, bool last_pass) {
  if (!start_written)  // fixed entries never change
    for (std::int32_t i : state_.moving) bond_start_[i] = p_[i];
  if constexpr (std::is_same_v<T, float>) {
    if (bond_lanes_)
      return bond_lanes_->Pass(bond_start_.data(), last_pass ? nullptr : p_.data(),
                               bond_correction_.data(), first_pass);
  }
  for (std::size_t r = 0; r + 1 < bond_rows_.size(); ++r) {
    const std::size_t first = bond_rows_[r], last = bond_rows_[r + 1];
    const std::int32_t i = bonds_[first].particle;
    const Vec3<T> pa = bond_start_[i];
    Vec3<T> sum{0, 0, 0};
    for (std::size_t b = first; b < last; ++b) {
      if (first_pass) bond_lambda_[b] = 0;  // a substep's solve starts at λ = 0
      const T alpha_tilde = bond_alpha_tilde_[b];
      if (alpha_tilde < 0) continue;
      const Vec3<T>& pb = bond_start_[bonds_[b].partner];
      const Vec3<T> d{pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
      const T length = Norm(d);
      if (!(length > 0)) continue;
      const T dlambda =
          (-(length - bonds_[b].rest_cu) - alpha_tilde * bond_lambda_[b]) / (T(1) + alpha_tilde);
      bond_lambda_[b] += dlambda;
      const T step = dlambda / length;
      for (int a = 0; a < 3; ++a) sum[a] += step * d[a];
    }
    for (int a = 0; a < 3; ++a) {
      if (!last_pass) p_[i][a] += sum[a];
      bond_correction_[i][a] = first_pass ? sum[a] : bond_correction_[i][a] + sum[a];
    }
  }
}

// Sibernetic's wall correction on the predicted positions [IAGT10], then the box's faces.
template <typename T>
void Xpbd<T>::ProjectBoundaries() {
  const T low[3] = {T(box_.xmin), T(box_.ymin), T(box_.zmin)};
  const T high[3] = {T(box_.xmax), T(box_.ymax), T(box_.zmax)};
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::size_t n = 0; n < state_.moving.size(); ++n) {
    const std::int32_t i = state_.moving[n];
    const Vec3<T> start = p_[i];
    const Float4 before{float(p_[i][0]), float(p_[i][1]), float(p_[i][2]), state_.position[i].w};
    Float4 after = before;
    CorrectAtWalls(k_, state_, i, &after, nullptr);
    // Only a wall's push changes p: the float copy's rounding must not reach a double run.
    if (after.x != before.x || after.y != before.y || after.z != before.z) {
      p_[i][0] += T(after.x) - T(before.x);
      p_[i][1] += T(after.y) - T(before.y);
      p_[i][2] += T(after.z) - T(before.z);
    }
    for (int a = 0; a < 3; ++a) p_[i][a] = std::clamp(p_[i][a], low[a], high[a]);
    const Vec3<T> push{p_[i][0] - start[0], p_[i][1] - start[1], p_[i][2] - start[2]};
    const T length = Norm(push);
    if (length > 0) wall_normal_[i] = {push[0] / length, push[1] / length, push[2] / length};
  }
}

// The contact velocity pass [M19 §4; Müller et al. 2007, PBD's velocity update]: a projection
// that pushed a particle out of a wall would leave it the push's speed, Δp/h, which grows as
// the substep shrinks. Along the push's normal the velocity becomes −e·v*_n for a particle that
// was approaching (v*_n < 0, v* the predicted velocity, e the restitution) and is never more
// than v*_n otherwise; the tangential part keeps Sibernetic's wall friction, 0.99 per step
// (sphFluid.cl, owval's CorrectAtWalls), as 0.99^(1/n) per substep.
template <typename T>
void Xpbd<T>::WallVelocity(std::int32_t i, const Vec3<T>& predicted, T restitution) {
  const Vec3<T>& n = wall_normal_[i];
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) return;
  Vec3<T>& v = v_[i];
  const T vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
  const T approach = predicted[0] * n[0] + predicted[1] * n[1] + predicted[2] * n[2];
  const T target = approach < 0 ? -restitution * approach : std::min(vn, approach);
  const T friction = approach < 0 ? T(wall_friction_) : T(1);
  for (int a = 0; a < 3; ++a) v[a] = (v[a] - vn * n[a]) * friction + target * n[a];
}

template <typename T>
void Xpbd<T>::UpdateVelocities(T dt) {
  const T scale = T(k_.scale), to_cu = T(1) / T(k_.scale);
  const T floor = T(box_.ymin) + T(k_.r0_cu), restitution = T(parameters_.floor_restitution);
  for (std::int32_t i : state_.moving) {
    const Vec3<T> predicted = v_[i];
    for (int a = 0; a < 3; ++a) {  // v* plus the constraints' change (bond_pushes.hpp: why)
      const T predicted_p = x_[i][a] + dt * predicted[a] * to_cu;
      v_[i][a] = predicted[a] + (p_[i][a] - predicted_p) * scale / dt;
    }
    WallVelocity(i, predicted, restitution);
    if (p_[i][1] <= floor && v_[i][1] < 0) v_[i][1] = -restitution * v_[i][1];
    x_[i] = p_[i];
    WriteFloatState(i);
  }
}

// Sibernetic's membrane pass (liquid pushed out along the membranes' plane normals), applied to
// the float copy; the moves are carried into the solver's positions.
template <typename T>
void Xpbd<T>::InteractWithMembranes() {
  if (matter_.membranes.empty()) return;
  const std::vector<std::int32_t>& moving = state_.moving;
  membrane_before_.resize(moving.size());  // the pass moves only moving particles
  for (std::size_t n = 0; n < moving.size(); ++n) membrane_before_[n] = state_.position[moving[n]];
  internal::InteractWithMembranes(k_, matter_, &state_, &membrane_scratch_, threads_);
  for (std::size_t n = 0; n < moving.size(); ++n) {
    const std::int32_t i = moving[n];
    const Float4 &a = membrane_before_[n], &b = state_.position[i];
    x_[i][0] += T(b.x) - T(a.x);
    x_[i][1] += T(b.y) - T(a.y);
    x_[i][2] += T(b.z) - T(a.z);
  }
}

// The membrane constraint's contacts for the step, at x(t), by Sibernetic's rule for which
// triangles act on a liquid particle (sphFluid.cl:1042-1322, phases/membranes.cpp): every
// triangle listed by an elastic neighbour j whose distance to it is under r0, the distance taken
// as Sibernetic takes it (MembraneDistance: z dropped, type codes kept), each triangle
// once per particle. The side is the one the particle is on now; a particle on a triangle's
// plane, or a degenerate triangle, makes no contact. Then the edges and vertices of those
// triangles near it (FindMembraneFeatures).
template <typename T>
void Xpbd<T>::FindMembraneContacts() {
  membrane_contacts_.clear();
  membrane_features_.clear();
  membrane_feature_owners_.clear();
  if (matter_.membranes.empty()) return;
  const float r0 = float(k_.r0_cu);
  std::vector<int> triangles;
  for (std::int32_t i : state_.moving) {
    const Float4 xi = state_.position[i];
    if (!IsLiquid(xi.w)) continue;
    triangles.clear();
    const Neighbour* slots = state_.slots(i);
    for (int n = 0; n < kSlots && slots[n].index >= 0; ++n) {
      const std::int32_t j = slots[n].index;
      const Float4 xj = state_.position[j];
      if (!IsElastic(xj.w)) continue;
      if (!(MembraneDistance(xi, xj) < r0)) continue;
      for (int t = 0; t < kMembraneSlots; ++t) {
        const int m = matter_.membrane_index[std::size_t(j) * kMembraneSlots + t];
        if (m < 0) break;
        if (std::find(triangles.begin(), triangles.end(), m) == triangles.end())
          triangles.push_back(m);
      }
    }
    const std::uint32_t first = std::uint32_t(membrane_contacts_.size());
    for (int m : triangles) {
      const std::array<int, 3>& tri = matter_.membranes[std::size_t(m)];
      const double side = SideOf(xi, tri, state_.position);
      if (side != 0) membrane_contacts_.push_back({i, tri, side > 0 ? T(1) : T(-1)});
    }
    FindMembraneFeatures(i, first);
  }
}

// The edges, then the vertices, of the particle's contact triangles (membrane_contacts_ from
// `triangles_begin` on) within r0 of it (3-D) at x(t), each once: where it could leave the
// membrane between triangles, with no triangle under it (ProjectMembranes). r0 is the
// selection's distance; a liquid particle moves a small part of it in a step. An edge within r0
// has a corner within √(r0² + (L/2)²), L its length: the others are skipped unmeasured
// (measuring every edge and vertex made demo1's 0.02 s run 1.8x slower, user time).
template <typename T>
void Xpbd<T>::FindMembraneFeatures(std::int32_t liquid, std::uint32_t triangles_begin) {
  const std::uint32_t triangles_end = std::uint32_t(membrane_contacts_.size());
  const Float4 x = state_.position[liquid];
  const double r0_2 = k_.r0_cu * k_.r0_cu;
  MeasureCornerDistances(x, triangles_begin, triangles_end);
  const auto add = [&](int u, int v) {
    const std::uint32_t owners = std::uint32_t(membrane_feature_owners_.size());
    if (AddFeatureOwners(x, u, v))
      membrane_features_.push_back({liquid,
                                    {u, v},
                                    owners,
                                    std::uint32_t(membrane_feature_owners_.size()),
                                    triangles_begin,
                                    triangles_end});
  };
  std::vector<std::uint64_t>& edges = feature_scratch_;  // u·2³² + v
  edges.clear();
  for (std::uint32_t c = triangles_begin; c < triangles_end; ++c)
    for (int k = 0; k < 3; ++k) {
      const auto& tri = membrane_contacts_[c].corners;
      const int u = std::min(tri[k], tri[(k + 1) % 3]), v = std::max(tri[k], tri[(k + 1) % 3]);
      const Float4 &pu = state_.position[u], &pv = state_.position[v];
      const double length2 = Norm2(pv, pu);
      if (!(std::min(corner_distance2_[u], corner_distance2_[v]) < r0_2 + length2 / 4)) continue;
      if (!(DistanceToSegment(x, pu, pv) < k_.r0_cu)) continue;
      const std::uint64_t key = std::uint64_t(u) << 32 | std::uint32_t(v);
      if (std::find(edges.begin(), edges.end(), key) != edges.end()) continue;
      edges.push_back(key);
      add(u, v);
    }
  for (std::uint32_t c = triangles_begin; c < triangles_end; ++c)
    for (int k : membrane_contacts_[c].corners) {
      if (!(corner_distance2_[k] < r0_2)) continue;
      corner_distance2_[k] = std::numeric_limits<double>::infinity();  // each vertex once
      add(k, -1);
    }
}

// corner_distance2_ (cu²) from x for every corner of the contact triangles [begin, end), each
// corner measured once.
template <typename T>
void Xpbd<T>::MeasureCornerDistances(const Float4& x, std::uint32_t begin, std::uint32_t end) {
  if (corner_visit_.size() != state_.size()) {
    corner_visit_.assign(state_.size(), 0);
    corner_distance2_.assign(state_.size(), 0);
  }
  ++corner_visit_stamp_;
  for (std::uint32_t c = begin; c < end; ++c)
    for (int k : membrane_contacts_[c].corners) {
      if (corner_visit_[std::size_t(k)] == corner_visit_stamp_) continue;
      corner_visit_[std::size_t(k)] = corner_visit_stamp_;
      corner_distance2_[std::size_t(k)] = Norm2(x, state_.position[std::size_t(k)]);
    }
}

// The membrane's triangles at the vertex `corner` (other_corner = −1) or at the edge corner–
// other_corner, each with the side of its plane x is on, appended to membrane_feature_owners_.
// False, with nothing appended, for a feature that cannot be where x leaves between triangles:
// x on a plane or a degenerate triangle (no side); an edge that is not between two triangles
// (a border of the membrane, which liquid may go round), or whose two triangles x is not over
// both of (a flat stretch, or a fold seen from its outside: there x cannot reach the far side of
// both planes without passing over a triangle, whose contact holds it); a vertex on a border
// (some edge at it in only one of its triangles).
template <typename T>
bool Xpbd<T>::AddFeatureOwners(const Float4& x, int corner, int other_corner) {
  const std::size_t start = membrane_feature_owners_.size();
  const auto give_up = [&] {
    membrane_feature_owners_.resize(start);
    return false;
  };
  std::array<int, 2 * kMembraneSlots> sides_seen{};  // the other corners, for the border test
  int seen = 0;
  for (int t = 0; t < kMembraneSlots; ++t) {
    const int m = matter_.membrane_index[std::size_t(corner) * kMembraneSlots + t];
    if (m < 0) break;
    const std::array<int, 3>& tri = matter_.membranes[std::size_t(m)];
    if (other_corner >= 0 && std::find(tri.begin(), tri.end(), other_corner) == tri.end()) continue;
    if (other_corner >= 0 && !OverTriangleSideOfEdge(x, tri, corner, other_corner, state_.position))
      return give_up();
    const double side = SideOf(x, tri, state_.position);
    if (side == 0) return give_up();
    membrane_feature_owners_.push_back({-1, tri, side > 0 ? T(1) : T(-1)});
    for (int k : tri)
      if (k != corner) sides_seen[std::size_t(seen++)] = k;
  }
  const std::size_t owners = membrane_feature_owners_.size() - start;
  if (other_corner >= 0) return owners == 2 ? true : give_up();
  for (int n = 0; n < seen; ++n)  // at an inner vertex every edge is in two of its triangles
    if (std::count(sides_seen.begin(), sides_seen.begin() + seen, sides_seen[std::size_t(n)]) != 2)
      return give_up();
  return owners > 0 ? true : give_up();
}

// Whether the feature's particle, at p, has left through the membrane where no triangle lies
// under it: it is on the far side of every plane of the triangles meeting at the feature (from
// the side it was on at x(t)), and its projection falls outside every one of its contact
// triangles (a triangle under it is the triangle contact's to hold).
template <typename T>
bool Xpbd<T>::FeatureCrossed(const MembraneFeature& feature) const {
  const Vec3<T>& q = p_[feature.liquid];
  const auto offsets = [&](const std::array<int, 3>& tri, Vec3<T>* ab, Vec3<T>* ac, Vec3<T>* aq) {
    const Vec3<T>&a = p_[tri[0]], &b = p_[tri[1]], &c = p_[tri[2]];
    *ab = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    *ac = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    *aq = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
  };
  Vec3<T> ab, ac, aq;
  for (std::uint32_t o = feature.owners_begin; o < feature.owners_end; ++o) {
    const MembraneContact& owner = membrane_feature_owners_[o];
    offsets(owner.corners, &ab, &ac, &aq);
    if (!(owner.side * SideOfPlane(ab, ac, aq) < 0)) return false;
  }
  T beta[3];
  for (std::uint32_t c = feature.triangles_begin; c < feature.triangles_end; ++c) {
    offsets(membrane_contacts_[c].corners, &ab, &ac, &aq);
    if (ProjectionIsOverTriangle(ab, ac, aq, beta)) return false;
  }
  return true;
}

// One pass of the membrane constraint over the step's contacts, Gauss-Seidel in their order (a
// particle near a flat stretch of membrane has several coplanar triangles; projected one after
// another, the later ones find the constraint met instead of adding the same push again): the
// triangle contacts, then the edges' and vertices' for particles that left where no triangle
// lies under them, taken back through the feature along the line from its nearest point (a
// vertex only when no edge took the particle back: edges come first).
// The clearance d kept from the plane is r0/1000. Not 0: a particle the constraint stopped sits
// at C = 0, and the next step's side would be the float rounding's (the side test's error at
// 50-90 cu is ~1e-5 cu; a test particle held at d = 0 was found on the far side the next step
// and fell through). Not r0 or any sizeable d: the selection's distance (z dropped) is not the
// plane's, so a contact can start with the particle already inside d and be thrown out to d; at
// r0/1000 that jump is under 0.002 cu.
template <typename T>
void Xpbd<T>::ProjectMembranes() {
  const T clearance = T(k_.r0_cu) / T(1000);
  const auto inverse_mass = [&](int k) { return moving_[std::size_t(k)] ? T(1) : T(0); };
  for (const MembraneContact& contact : membrane_contacts_) {
    const auto& [a, b, c] = contact.corners;
    ProjectPointOffTriangle(&p_[contact.liquid], &p_[a], &p_[b], &p_[c], T(1), inverse_mass(a),
                            inverse_mass(b), inverse_mass(c), contact.side, clearance);
  }
  for (const MembraneFeature& feature : membrane_features_) {
    if (!FeatureCrossed(feature)) continue;
    const auto [u, v] = feature.corners;
    T lambda = 0;  // a contact: compliance 0, λ unused
    if (v < 0)
      ProjectPointOffVertex(&p_[feature.liquid], &p_[u], T(1), inverse_mass(u), T(-1), clearance,
                            T(0), &lambda);
    else
      ProjectPointOffEdge(&p_[feature.liquid], &p_[u], &p_[v], T(1), inverse_mass(u),
                          inverse_mass(v), T(-1), clearance, T(0), &lambda);
  }
}

template <typename T>
void Xpbd<T>::SaveState(std::string* out) const {
  StateWriter w(out);
  PutStateHeader(w, name(), state_.size(), step_);
  PutParticleState(w, state_);
  w.Put(pressure_acceleration_), w.Put(x_), w.Put(v_), w.Put(p_), w.Put(position_remainder_);
  w.Put(matter_.muscle_activation);
}

template <typename T>
void Xpbd<T>::RestoreState(const std::string& state, const std::string& source) {
  StateReader r(state, source);
  const std::size_t n = state_.size();
  const std::uint64_t steps = GetStateHeader(r, name(), n);
  GetParticleState(r, &state_);
  r.GetSized(&pressure_acceleration_, n);
  r.GetSized(&x_, n), r.GetSized(&v_, n), r.GetSized(&p_, n), r.GetSized(&position_remainder_, n);
  r.GetSized(&matter_.muscle_activation, std::size_t(kMuscles));
  if (!r.done()) r.Fail("bytes left after the state");
  step_ = std::size_t(steps);
}

template <typename T>
std::vector<float> Xpbd<T>::Density() const {
  return output_density_.Of(k_, grid_, state_);
}

template <typename T>
std::string Xpbd<T>::parameters() const {
  std::ostringstream s;
  s << "substeps = " << substeps_ << (parameters_.substeps > 0 ? "" : " (derived)")
    << ", iterations = " << parameters_.iterations
    << ", density_passes = " << parameters_.density_passes
    << ", damping_budget = " << parameters_.damping_budget
    << ", density_compliance = " << density_compliance_
    << (parameters_.density_compliance > 0 ? "" : " (derived)")
    << ", bond_compliance_scale = " << parameters_.bond_compliance_scale
    << ", rest_density = " << rest_density_ << (parameters_.rest_density > 0 ? "" : " (derived)")
    << ", sibernetic_target_density = " << std::setprecision(9) << sibernetic_target_density_
    << std::setprecision(6) << ", floor_restitution = " << parameters_.floor_restitution
    << ", muscle_strength = " << parameters_.muscle_strength
    << ", viscosity = " << parameters_.viscosity
    << ", surface_tension = " << parameters_.surface_tension
    << ", pressure_force = " << parameters_.pressure_force
    << ", membranes = " << (parameters_.membranes ? "constraint" : "pass")
    << ", reciprocal_lists = " << parameters_.reciprocal_lists
    << ", tensile_correction = " << parameters_.tensile_correction;
  if (tensile_.on())
    s << " (n = " << parameters_.tensile_exponent << ", dq = " << parameters_.tensile_distance_h
      << " h)";
  if (parameters_.body_push_only) s << ", body_push_only = 1";  // off: the string as before
  s << ", scalar = " << (sizeof(T) == 4 ? "float" : "double");
  return s.str();
}

template <typename T>
Solver::NonFinite Xpbd<T>::FirstNonFinite() const {
  return FirstNonFiniteOf(state_.position, state_.velocity, state_.moving);
}

template class Xpbd<float>;
template class Xpbd<double>;

}  // namespace owval::engine::internal
