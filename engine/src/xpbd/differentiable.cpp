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
  b += FieldBytes(x) + FieldBytes(v) + FieldBytes(a) + FieldBytes(p_predicted) +
       FieldBytes(p_final) + FieldBytes(rho);
  for (const auto& f : p_before_density) b += FieldBytes(f);
  for (const auto& f : p_before_bonds) b += FieldBytes(f);
  for (const auto& f : p_before_box) b += FieldBytes(f);
  for (const auto& l : lambda_density) b += FieldBytes(l);
  for (const auto& l : lambda_bonds) b += FieldBytes(l);
  for (const auto& m : density_multipliers) b += FieldBytes(m[0]) + FieldBytes(m[1]);
  for (const auto& f : bond_partners) b += FieldBytes(f);
  for (const auto& f : bond_particles) b += FieldBytes(f);
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
  for (std::size_t i = 0; i < S.n; ++i) {
    S.type.push_back(config.position[i][3]);
    if (!IsBoundary(config.position[i][3])) {
      S.moving[i] = 1;
      S.movers.push_back(std::int32_t(i));
    }
  }
  for (std::size_t e = 0; e < config.elastic_count(); ++e)
    for (int slot = 0; slot < kConnectionSlots; ++slot) {
      const Row4& c = config.connection[e * kConnectionSlots + slot];
      if (c[0] < 0) break;
      const std::int32_t j = static_cast<std::int32_t>(c[0]);
      const bool body = IsWormBody(config.position[e][3]) && IsWormBody(config.position[j][3]);
      S.bonds.push_back({std::int32_t(e), j, double(c[1]), body ? 0 : 1, int(c[2])});
    }
  S.activation.assign(96, 0.0f);
  S.dt = k.time_step_s;
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
  t[kAlphaDensity] = constants.xpbd.density_compliance;
  t[kFloorHeight] = config.box.ymin;
  t[kRestitution] = constants.xpbd.floor_restitution;
  t[kMuscleStrength] = constants.xpbd.muscle_strength;
  return t;
}

void StepForward(const Setup<double>& S, const Parameters<double>& theta, const Field<double>& x,
                 const Field<double>& v, Field<double>* x_next, Field<double>* v_next,
                 StepTape* tape) {
  StepTape local;
  StepTape& t = tape ? *tape : local;
  t.nb = FindNeighbours(S, x);
  t.x = x;
  t.v = v;
  SphDensity(S, t.nb, x, &t.rho);
  Forces(S, t.nb, x, v, t.rho, theta[kViscosity], &t.a);
  Predict(S, x, v, t.a, &t.p_predicted);
  Field<double> p = t.p_predicted;
  std::vector<double> ld(S.n, 0.0), lb(S.bonds.size(), 0.0);
  const double V0 = RestVolume(S, theta), at = DensityAlphaTilde(S, theta);
  const std::size_t K = std::size_t(std::max(S.iterations, 0));
  t.p_before_density.resize(K), t.p_before_bonds.resize(K), t.p_before_box.resize(K);
  t.lambda_density.resize(K), t.lambda_bonds.resize(K);
  t.density_multipliers.resize(K), t.bond_partners.resize(K), t.bond_particles.resize(K);
  for (std::size_t k = 0; k < K; ++k) {
    t.p_before_density[k] = p;
    t.lambda_density[k] = ld;
    DensityPass(S, t.nb, V0, at, &p, &ld, &t.density_multipliers[k]);
    t.p_before_bonds[k] = p;
    t.lambda_bonds[k] = lb;
    t.bond_partners[k].resize(S.bonds.size());
    t.bond_particles[k].resize(S.bonds.size());
    BondPass(S, theta, &p, &lb, &t.bond_partners[k], &t.bond_particles[k]);
    t.p_before_box[k] = p;
    BoxPass(S, theta[kFloorHeight], &p);
  }
  t.p_final = p;
  UpdateVelocity(S, theta[kFloorHeight], theta[kRestitution], x, p, v_next, x_next);
}

void StepBackward(const Setup<double>& S, const Parameters<double>& theta, const StepTape& t,
                  Field<double>* x_bar, Field<double>* v_bar, Parameters<double>* theta_bar) {
  const Field<double> x_next_bar = *x_bar, v_next_bar = *v_bar;
  x_bar->assign(S.n, Vec3<double>{0, 0, 0});
  v_bar->assign(S.n, Vec3<double>{0, 0, 0});
  Field<double> p_bar(S.n, Vec3<double>{0, 0, 0});
  Parameters<double>& tb = *theta_bar;
  UpdateVelocityBackward(S, theta[kFloorHeight], theta[kRestitution], t.x, t.p_final, v_next_bar,
                         x_next_bar, x_bar, &p_bar, &tb[kRestitution]);
  std::vector<double> ld_bar(S.n, 0.0), lb_bar(S.bonds.size(), 0.0);
  const double V0 = RestVolume(S, theta), at = DensityAlphaTilde(S, theta);
  double V0_bar = 0, at_bar = 0;
  for (std::size_t k = t.p_before_density.size(); k-- > 0;) {
    BoxPassBackward(S, theta[kFloorHeight], t.p_before_box[k], &p_bar, &tb[kFloorHeight]);
    BondPassBackward(S, theta, t.p_before_bonds[k], t.lambda_bonds[k], &p_bar, &lb_bar, &tb,
                     &t.bond_partners[k], &t.bond_particles[k]);
    DensityPassBackward(S, t.nb, V0, at, t.p_before_density[k], t.lambda_density[k], &p_bar,
                        &ld_bar, &V0_bar, &at_bar, &t.density_multipliers[k]);
  }
  // λ starts at 0 each step: its cotangent ends here. A fixed particle's x̄ is its position's
  // gradient (it enters every neighbour's kernels).
  Field<double> a_bar(S.n, Vec3<double>{0, 0, 0});
  PredictBackward(S, p_bar, x_bar, v_bar, &a_bar);
  std::vector<double> rho_bar(S.n, 0.0);
  ForcesBackward(S, t.nb, t.x, t.v, t.rho, theta[kViscosity], a_bar, x_bar, v_bar, &rho_bar,
                 &tb[kViscosity]);
  SphDensityBackward(S, t.nb, t.x, rho_bar, x_bar);
  tb[kRestDensity] += V0_bar * -V0 / theta[kRestDensity];
  tb[kAlphaDensity] += at_bar / (S.dt * S.dt);
}

}  // namespace owval::engine::internal::adjoint
