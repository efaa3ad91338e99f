#include "xpbd/differentiable.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_map>

#include "kernels/kernels.hpp"
#include "kernels/sph_constants.hpp"
#include "state/particle_state.hpp"
#include "xpbd/xpbd.hpp"

namespace owval::engine::internal::adjoint {
namespace {

// The moving particles' entries of a per-particle vector, in Setup::movers' order, and back.
template <typename V>
void Gather(const Setup<double>& S, const std::vector<V>& all, std::vector<V>* movers) {
  movers->resize(S.movers.size());
  for (std::size_t k = 0; k < S.movers.size(); ++k) (*movers)[k] = all[S.movers[k]];
}
template <typename V>
void Scatter(const Setup<double>& S, const std::vector<V>& movers, std::vector<V>* all) {
  for (std::size_t k = 0; k < S.movers.size(); ++k) (*all)[S.movers[k]] = movers[k];
}
template <typename V>
void ZeroMovers(const Setup<double>& S, std::vector<V>* all) {
  for (std::int32_t i : S.movers) (*all)[i] = V{};
}

// A floor no particle reaches: a bond substep's velocity update never restitutes.
constexpr double kNoFloor = 1e300;

std::int64_t CellKey(std::int64_t cx, std::int64_t cy, std::int64_t cz) {
  return (cx * 1000003 + cy) * 1000033 + cz;
}

template <typename V>
std::size_t FieldBytes(const std::vector<V>& f) {
  return f.size() * sizeof(V);
}

}  // namespace

std::size_t StepTape::Bytes() const {
  std::size_t b = (nb.start.size() + nb.index.size()) * sizeof(std::int32_t);
  b += FieldBytes(x) + FieldBytes(v) + FieldBytes(a) + FieldBytes(rho);
  for (const SubstepTape& s : substeps) {
    b += FieldBytes(s.x) + FieldBytes(s.p_final) + FieldBytes(s.v);
    for (const PassTape& p : s.passes)
      b += FieldBytes(p.p_before_density) + FieldBytes(p.p_before_box) +
           FieldBytes(p.lambda_density) + FieldBytes(p.dlambda) + FieldBytes(p.denominator) +
           FieldBytes(p.lambda_bonds) + FieldBytes(p.bond_partners) + FieldBytes(p.bond_particles);
  }
  return b;
}

Setup<double>::Cells HashCells(const Setup<double>& S, const Field<double>& x, bool moving) {
  const double h = S.h + S.neighbour_skin;
  Setup<double>::Cells cells;
  for (std::size_t i = 0; i < S.n; ++i) {
    if (bool(S.moving[i]) != moving) continue;
    const std::int64_t c[3] = {std::int64_t(std::floor(x[i][0] / h)),
                               std::int64_t(std::floor(x[i][1] / h)),
                               std::int64_t(std::floor(x[i][2] / h))};
    cells[CellKey(c[0], c[1], c[2])].push_back(std::int32_t(i));
  }
  return cells;
}

// Candidates come from the fixed particles' cells (hashed once, at their configuration
// positions: a fixed particle moved by a gradient check's 1e-4 cu can only be missed at a
// distance beyond h, where every kernel is zero) and the moving particles' cells at x.
Neighbours FindNeighbours(const Setup<double>& S, const Field<double>& x) {
  const double h = S.h + S.neighbour_skin, h2 = h * h;
  const Setup<double>::Cells moving_cells = HashCells(S, x, true);
  const Setup<double>::Cells fixed_cells =
      S.fixed_cells ? Setup<double>::Cells{} : HashCells(S, x, false);
  const Setup<double>::Cells* lists[2] = {S.fixed_cells ? S.fixed_cells.get() : &fixed_cells,
                                          &moving_cells};
  auto cell = [&](const Vec3<double>& p, int a) { return std::int64_t(std::floor(p[a] / h)); };
  Neighbours nb;
  nb.start.assign(S.n + 1, 0);
  std::size_t at = 0;
  for (std::size_t i = 0; i < S.n; ++i) {
    nb.start[i] = std::int32_t(nb.index.size());
    if (at < S.movers.size() && S.movers[at] == std::int32_t(i)) {
      ++at;
      const std::int64_t c[3] = {cell(x[i], 0), cell(x[i], 1), cell(x[i], 2)};
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            for (const Setup<double>::Cells* cells : lists) {
              const auto it = cells->find(CellKey(c[0] + dx, c[1] + dy, c[2] + dz));
              if (it == cells->end()) continue;
              for (std::int32_t j : it->second) {
                if (j == std::int32_t(i)) continue;
                const Vec3<double> d = Sub(x[i], x[j]);
                if (Dot(d, d) < h2) nb.index.push_back(j);
              }
            }
          }
    }
  }
  nb.start[S.n] = std::int32_t(nb.index.size());
  return nb;
}

Setup<double> SetupOf(const SiberneticConfig& config, const PhysicsConstants& constants) {
  const SphConstants k = SphConstants::From(constants);
  Setup<double> S;
  S.n = config.particle_count();
  S.moving.assign(S.n, 0);
  S.slot.assign(S.n, -1);
  for (std::size_t i = 0; i < S.n; ++i) {
    S.type.push_back(config.position[i][3]);
    if (!IsBoundary(config.position[i][3])) {
      S.moving[i] = 1;
      S.slot[i] = std::int32_t(S.movers.size());
      S.movers.push_back(std::int32_t(i));
    }
  }
  const std::size_t elastic = config.elastic_count();  // counts the particles: once
  for (std::size_t e = 0; e < elastic; ++e)
    for (int slot = 0; slot < kConnectionSlots; ++slot) {
      const Row4& c = config.connection[e * kConnectionSlots + slot];
      if (c[0] < 0) break;
      const std::int32_t j = static_cast<std::int32_t>(c[0]);
      const bool body = IsWormBody(config.position[e][3]) && IsWormBody(config.position[j][3]);
      S.bonds.push_back({std::int32_t(e), j, double(c[1]), body ? 0 : 1, int(c[2])});
    }
  S.activation.assign(96, 0.0f);
  S.substeps = SubstepsOf(config, constants);
  S.density_passes = std::max(constants.xpbd.density_passes, 0);
  if (S.density_passes > 0) {  // as the run's Xpbd<double> computes H and h (xpbd.cpp, Step)
    const int m = S.density_passes;
    S.substeps = (S.substeps + m - 1) / m;
    S.correction_dt = double(k.time_step_s) / double(m);
    S.dt = S.correction_dt / double(S.substeps);
  } else {
    S.dt = double(k.time_step_s) / double(S.substeps);
  }
  S.s = k.scale;
  S.mass = k.mass_kg;
  S.h = k.h_cu;
  S.poly6_cu = Wpoly6Coefficient(S.h);
  S.spiky_cu = SpikyGradientCoefficient(S.h);
  S.hs = double(k.h_cu) * double(k.scale);
  S.hs2 = S.hs * S.hs;
  S.poly6_m = Wpoly6Coefficient(S.hs);
  S.viscosity_beta = 1.5 * S.mass * -SpikyGradientCoefficient(S.hs) / 1000.0;
  S.cohesion_gamma = double(k.surface_tension) / S.mass;
  for (int a = 0; a < 3; ++a) S.gravity[a] = k.gravity[a];
  S.r0 = k.r0_cu;
  const Box& b = config.box;
  S.low[0] = b.xmin, S.low[1] = b.ymin, S.low[2] = b.zmin;
  S.high[0] = b.xmax, S.high[1] = b.ymax, S.high[2] = b.zmax;
  S.bond_compliance_scale = constants.xpbd.bond_compliance_scale;
  S.iterations = constants.xpbd.iterations;
  S.viscosity = constants.xpbd.viscosity != 0;
  S.surface_tension = constants.xpbd.surface_tension != 0;
  Field<double> x(S.n);
  for (std::size_t i = 0; i < S.n; ++i)
    x[i] = {config.position[i][0], config.position[i][1], config.position[i][2]};
  S.fixed_cells = std::make_shared<const Setup<double>::Cells>(HashCells(S, x, false));
  return S;
}

Parameters<double> DefaultParametersOf(const SiberneticConfig& config,
                                       const PhysicsConstants& constants) {
  Parameters<double> t{};
  // The run's own derivation of ρ_rest (xpbd.cpp), so both start from the same value.
  t[kRestDensity] = constants.xpbd.rest_density > 0
                        ? constants.xpbd.rest_density
                        : Xpbd<double>(config, constants, 1).rest_density();
  t[kBondStiffnessBody] = constants.elasticity_coefficient;
  t[kBondStiffnessOther] = constants.elasticity_coefficient * constants.non_worm_body_spring_factor;
  t[kViscosity] = 1;
  t[kAlphaDensity] = DensityComplianceOf(config, constants);
  t[kFloorHeight] = config.box.ymin;
  t[kRestitution] = constants.xpbd.floor_restitution;
  t[kMuscleStrength] = constants.xpbd.muscle_strength;
  return t;
}

namespace {

// Per-particle working vectors of a step's substeps, sized once per step; a substep touches
// only the moving particles' entries.
struct Work {
  explicit Work(const Setup<double>& S)
      : lambda(S.n, 0.0),
        lambda_bar(S.n, 0.0),
        bond_lambda_bar(S.bonds.size(), 0.0),
        multipliers{std::vector<double>(S.n, 0.0), std::vector<double>(S.n, 0.0)},
        x_in_bar(S.n, Vec3<double>{0, 0, 0}),
        v_in_bar(S.n, Vec3<double>{0, 0, 0}) {}
  std::vector<double> lambda, lambda_bar, bond_lambda_bar;
  std::array<std::vector<double>, 2> multipliers;  // Δλ, denominators
  Field<double> x_in_bar, v_in_bar;
};

// One density pass, with what its backward needs recorded in pt: the positions and
// multipliers before it, its Δλ and denominators.
void RecordedDensityPass(const Setup<double>& S, const Neighbours& nb, double V0, double at,
                         Field<double>* p, Work* w, PassTape* pt) {
  Gather(S, *p, &pt->p_before_density);
  Gather(S, w->lambda, &pt->lambda_density);
  DensityPass(S, nb, V0, at, p, &w->lambda, &w->multipliers);
  Gather(S, w->multipliers[0], &pt->dlambda);
  Gather(S, w->multipliers[1], &pt->denominator);
}

// Its backward from the record (p, w's multipliers: working fields, overwritten).
void DensityPassBackwardFromTape(const Setup<double>& S, const Neighbours& nb, double V0, double at,
                                 const PassTape& pt, Field<double>* p, Work* w,
                                 Field<double>* p_bar, double* V0_bar, double* at_bar) {
  Scatter(S, pt.p_before_density, p);
  Scatter(S, pt.lambda_density, &w->lambda);
  Scatter(S, pt.dlambda, &w->multipliers[0]);
  Scatter(S, pt.denominator, &w->multipliers[1]);
  DensityPassBackward(S, nb, V0, at, *p, w->lambda, p_bar, &w->lambda_bar, V0_bar, at_bar,
                      &w->multipliers);
}

// One substep [M19]: predict, K passes, velocity update; x, v (every particle, fixed entries
// constant) are the substep's input and output, p its working positions (fixed entries = x).
void SubstepForward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& t,
                    Field<double>* x, Field<double>* v, Field<double>* p, Work* w,
                    SubstepTape* st) {
  const double V0 = RestVolume(S, theta), at = DensityAlphaTilde(S, theta);
  std::vector<double> lb(S.bonds.size(), 0.0);
  ZeroMovers(S, &w->lambda);
  Gather(S, *x, &st->x);
  Predict(S, *x, *v, t.a, p, false);
  st->passes.resize(std::size_t(std::max(S.iterations, 0)));
  for (PassTape& pt : st->passes) {
    RecordedDensityPass(S, t.nb, V0, at, p, w, &pt);
    pt.lambda_bonds = lb;
    pt.bond_partners.resize(S.bonds.size());
    pt.bond_particles.resize(S.bonds.size());
    BondPass(S, theta, p, &lb, &pt.bond_partners, &pt.bond_particles);
    Gather(S, *p, &pt.p_before_box);
    BoxPass(S, theta[kFloorHeight], p);
  }
  Gather(S, *p, &st->p_final);
  UpdateVelocity(S, theta[kFloorHeight], theta[kRestitution], *x, *p, v, x, false);
}

// The backward of one substep on the moving particles' cotangents: x_bar, v_bar (of the
// substep's output in, of its input out), p_bar (its fixed entries collect the projections'
// cotangents of fixed neighbours over the step), a_bar; x, p are working fields whose fixed
// entries are the step's x.
void SubstepBackward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& t,
                     const SubstepTape& st, Field<double>* x, Field<double>* p, Work* w,
                     Field<double>* x_bar, Field<double>* v_bar, Field<double>* p_bar,
                     Field<double>* a_bar, Parameters<double>* theta_bar, double* V0_bar,
                     double* at_bar) {
  const double V0 = RestVolume(S, theta), at = DensityAlphaTilde(S, theta);
  Parameters<double>& tb = *theta_bar;
  Scatter(S, st.x, x);
  Scatter(S, st.p_final, p);
  ZeroMovers(S, p_bar);
  ZeroMovers(S, &w->x_in_bar);
  ZeroMovers(S, &w->v_in_bar);
  UpdateVelocityBackward(S, theta[kFloorHeight], theta[kRestitution], *x, *p, *v_bar, *x_bar,
                         &w->x_in_bar, p_bar, &tb[kRestitution], false);
  ZeroMovers(S, &w->lambda_bar);  // λ starts at 0 each substep: no cotangent crosses substeps
  std::fill(w->bond_lambda_bar.begin(), w->bond_lambda_bar.end(), 0.0);
  for (std::size_t k = st.passes.size(); k-- > 0;) {
    const PassTape& pt = st.passes[k];
    Scatter(S, pt.p_before_box, p);
    BoxPassBackward(S, theta[kFloorHeight], *p, p_bar, &tb[kFloorHeight]);
    BondPassBackward(S, theta, *p, pt.lambda_bonds, p_bar, &w->bond_lambda_bar, &tb,
                     &pt.bond_partners, &pt.bond_particles);
    DensityPassBackwardFromTape(S, t.nb, V0, at, pt, p, w, p_bar, V0_bar, at_bar);
  }
  PredictBackward(S, *p_bar, &w->x_in_bar, &w->v_in_bar, a_bar, false);
  for (std::int32_t i : S.movers) {
    (*x_bar)[i] = w->x_in_bar[i];
    (*v_bar)[i] = w->v_in_bar[i];
  }
}

// The split step's bond substep: predict, K Jacobi bond passes, v = (p − x)s/h (no floor
// restitution: the correction applies it), x' = p.
void BondSubstepForward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& t,
                        Field<double>* x, Field<double>* v, Field<double>* p, SubstepTape* st) {
  std::vector<double> lb(S.bonds.size(), 0.0);
  Gather(S, *x, &st->x);
  Predict(S, *x, *v, t.a, p, false);
  st->passes.resize(std::size_t(std::max(S.iterations, 0)));
  for (PassTape& pt : st->passes) {
    pt.lambda_bonds = lb;
    pt.bond_partners.resize(S.bonds.size());
    pt.bond_particles.resize(S.bonds.size());
    BondPassJacobi(S, theta, p, &lb, &pt.bond_partners, &pt.bond_particles);
  }
  Gather(S, *p, &st->p_final);
  UpdateVelocity(S, -kNoFloor, 0.0, *x, *p, v, x, false);
}

void BondSubstepBackward(const Setup<double>& S, const Parameters<double>& theta,
                         const SubstepTape& st, Field<double>* x, Field<double>* p, Work* w,
                         Field<double>* x_bar, Field<double>* v_bar, Field<double>* p_bar,
                         Field<double>* a_bar, Parameters<double>* theta_bar) {
  Scatter(S, st.x, x);
  Scatter(S, st.p_final, p);
  ZeroMovers(S, p_bar);
  ZeroMovers(S, &w->x_in_bar);
  ZeroMovers(S, &w->v_in_bar);
  double e_bar = 0;  // no restitution in a bond substep
  UpdateVelocityBackward(S, -kNoFloor, 0.0, *x, *p, *v_bar, *x_bar, &w->x_in_bar, p_bar, &e_bar,
                         false);
  std::fill(w->bond_lambda_bar.begin(), w->bond_lambda_bar.end(), 0.0);
  for (std::size_t k = st.passes.size(); k-- > 0;) {
    const PassTape& pt = st.passes[k];
    BondPassJacobiBackward(S, theta, pt.lambda_bonds, pt.bond_particles, pt.bond_partners, p_bar,
                           &w->bond_lambda_bar, theta_bar);
  }
  PredictBackward(S, *p_bar, &w->x_in_bar, &w->v_in_bar, a_bar, false);
  for (std::int32_t i : S.movers) {
    (*x_bar)[i] = w->x_in_bar[i];
    (*v_bar)[i] = w->v_in_bar[i];
  }
}

// The split step's correction over H: K × {density constraints (α̃ = α/H²), box} from p = x,
// then CorrectVelocity. Its tape: x (input), v (input velocity), p_final and the passes.
void CorrectionForward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& t,
                       Field<double>* x, Field<double>* v, Field<double>* p, Work* w,
                       SubstepTape* st) {
  const double V0 = RestVolume(S, theta), at = DensityAlphaTilde(S, theta);
  ZeroMovers(S, &w->lambda);
  Gather(S, *x, &st->x);
  Gather(S, *v, &st->v);
  for (std::int32_t i : S.movers) (*p)[i] = (*x)[i];
  st->passes.resize(std::size_t(std::max(S.iterations, 0)));
  for (PassTape& pt : st->passes) {
    RecordedDensityPass(S, t.nb, V0, at, p, w, &pt);
    Gather(S, *p, &pt.p_before_box);
    BoxPass(S, theta[kFloorHeight], p);
  }
  Gather(S, *p, &st->p_final);
  CorrectVelocity(S, S.correction_dt, theta[kFloorHeight], theta[kRestitution], *x, *p, v, x);
}

void CorrectionBackward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& t,
                        const SubstepTape& st, Field<double>* x, Field<double>* p, Work* w,
                        Field<double>* x_bar, Field<double>* v_bar, Field<double>* p_bar,
                        Parameters<double>* theta_bar, double* V0_bar, double* at_bar) {
  const double V0 = RestVolume(S, theta), at = DensityAlphaTilde(S, theta);
  Parameters<double>& tb = *theta_bar;
  Field<double> v_in(S.n, Vec3<double>{0, 0, 0});
  Scatter(S, st.x, x);
  Scatter(S, st.p_final, p);
  Scatter(S, st.v, &v_in);
  ZeroMovers(S, p_bar);
  ZeroMovers(S, &w->x_in_bar);
  ZeroMovers(S, &w->v_in_bar);
  CorrectVelocityBackward(S, S.correction_dt, theta[kFloorHeight], theta[kRestitution], *x, *p,
                          v_in, *v_bar, *x_bar, &w->x_in_bar, &w->v_in_bar, p_bar,
                          &tb[kRestitution]);
  ZeroMovers(S, &w->lambda_bar);
  for (std::size_t k = st.passes.size(); k-- > 0;) {
    const PassTape& pt = st.passes[k];
    Scatter(S, pt.p_before_box, p);
    BoxPassBackward(S, theta[kFloorHeight], *p, p_bar, &tb[kFloorHeight]);
    DensityPassBackwardFromTape(S, t.nb, V0, at, pt, p, w, p_bar, V0_bar, at_bar);
  }
  for (std::int32_t i : S.movers) {  // p started as x
    for (int c = 0; c < 3; ++c) (*x_bar)[i][c] = w->x_in_bar[i][c] + (*p_bar)[i][c];
    (*v_bar)[i] = w->v_in_bar[i];
  }
}

}  // namespace

void StepForward(const Setup<double>& S, const Parameters<double>& theta, const Field<double>& x,
                 const Field<double>& v, Field<double>* x_next, Field<double>* v_next,
                 StepTape* tape) {
  StepTape local;
  StepTape& t = tape ? *tape : local;
  t.nb = FindNeighbours(S, x);
  t.x = x;
  t.v = v;
  SphDensity(S, t.nb, x, &t.rho);
  Forces(S, t.nb, x, v, t.rho, theta[kViscosity], &t.a);  // held over the substeps
  *x_next = x;
  v_next->assign(S.n, Vec3<double>{0, 0, 0});  // a fixed particle's velocity is zero
  for (std::int32_t i : S.movers) (*v_next)[i] = v[i];
  Field<double> p = x;
  Work w(S);
  if (S.density_passes <= 0) {
    t.substeps.resize(std::size_t(std::max(S.substeps, 1)));
    for (SubstepTape& st : t.substeps) SubstepForward(S, theta, t, x_next, v_next, &p, &w, &st);
    return;
  }
  // m × {inner bond substeps, one correction}: the tape holds them in that order.
  const std::size_t inner = std::size_t(std::max(S.substeps, 1));
  t.substeps.resize(std::size_t(S.density_passes) * (inner + 1));
  for (std::size_t k = 0; k < t.substeps.size(); ++k) {
    SubstepTape& st = t.substeps[k];
    st.correction = (k + 1) % (inner + 1) == 0;
    if (st.correction)
      CorrectionForward(S, theta, t, x_next, v_next, &p, &w, &st);
    else
      BondSubstepForward(S, theta, t, x_next, v_next, &p, &st);
  }
}

void StepBackward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& t,
                  Field<double>* x_bar, Field<double>* v_bar, Parameters<double>* theta_bar) {
  const Field<double> x_next_bar = *x_bar;
  Parameters<double>& tb = *theta_bar;
  Field<double> x = t.x, p = t.x, p_bar(S.n, Vec3<double>{0, 0, 0}), a_bar = p_bar;
  Work w(S);
  double V0_bar = 0, at_bar = 0;
  for (std::size_t s = t.substeps.size(); s-- > 0;) {
    const SubstepTape& st = t.substeps[s];
    if (S.density_passes <= 0)
      SubstepBackward(S, theta, t, st, &x, &p, &w, x_bar, v_bar, &p_bar, &a_bar, &tb, &V0_bar,
                      &at_bar);
    else if (st.correction)
      CorrectionBackward(S, theta, t, st, &x, &p, &w, x_bar, v_bar, &p_bar, &tb, &V0_bar, &at_bar);
    else
      BondSubstepBackward(S, theta, st, &x, &p, &w, x_bar, v_bar, &p_bar, &a_bar, &tb);
  }
  // A fixed particle: x' = x, so x̄ = x̄' + every projection's cotangent of it as a neighbour;
  // its velocity never enters (v' = 0).
  for (std::size_t i = 0; i < S.n; ++i)
    if (!S.moving[i]) {
      for (int c = 0; c < 3; ++c) (*x_bar)[i][c] = x_next_bar[i][c] + p_bar[i][c];
      (*v_bar)[i] = Vec3<double>{0, 0, 0};
    }
  std::vector<double> rho_bar(S.n, 0.0);
  ForcesBackward(S, t.nb, t.x, t.v, t.rho, theta[kViscosity], a_bar, x_bar, v_bar, &rho_bar,
                 &tb[kViscosity]);
  SphDensityBackward(S, t.nb, t.x, rho_bar, x_bar);
  tb[kRestDensity] += V0_bar * -RestVolume(S, theta) / theta[kRestDensity];
  tb[kAlphaDensity] += at_bar / (DensityDt(S) * DensityDt(S));
}

}  // namespace owval::engine::internal::adjoint
