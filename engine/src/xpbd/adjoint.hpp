#pragma once
// The XPBD step as pure kernels, each followed by its backward kernel: the vector-Jacobian
// product (VJP) that maps the cotangent of the kernel's outputs to the cotangents of its inputs
// (positions, velocities, multipliers, parameters). No automatic differentiation: each VJP is
// derived by hand in the comment above it and checked against central differences by
// `owval gradcheck` (engine/src/xpbd/gradcheck.cpp).
//
// Conventions: x, p in configuration units (cu), v in m/s, s = metres per cu, dt in s. A
// backward kernel ADDS into the cotangents it is given (bar arrays), so a caller can sum the
// contributions of several uses; "out_bar" arrays that the kernel maps in place are documented.
// Neighbour lists (pairs within h + skin at the step's start) are held constant through a step:
// every kernel vanishes at its support's edge and is evaluated with its own r < h test, so a
// list change is continuous while no pair moves more than the skin in one step (docs/xpbd.md).
//
//   [MMC16] Macklin, Müller, Chentanez. XPBD, MIG 2016 (eqs. 17-18).
//   [MM13]  Macklin, Müller. Position based fluids, TOG 32(4) 2013 (eqs. 1-12).
//   Sibernetic's viscosity and cohesion: sphFluid.cl:580-657 (engine/src/phases/forces.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "xpbd/projections.hpp"

namespace owval::engine::internal::adjoint {

template <typename T>
using Field = std::vector<Vec3<T>>;

// The differentiable parameters, in these units:
enum Parameter : int {
  kRestDensity = 0,    // ρ_rest, kg/m³
  kBondStiffnessBody,  // k of bonds between two worm-body particles, s⁻²
  kBondStiffnessOther,  // k of every other bond (Sibernetic's k·non_worm_body_spring_factor), s⁻²
  kViscosity,           // multiplier of Sibernetic's pair viscosity coefficients (1 = Sibernetic's)
  kAlphaDensity,        // compliance of the density constraint, s² per unit mass
  kFloorHeight,         // y of the floor the box clamp and restitution use, cu
  kRestitution,         // normal velocity kept (reversed) at the floor
  kMuscleStrength,      // bond k(t) = k·(1 + activation·strength)
  kParameterCount
};
template <typename T>
using Parameters = std::array<T, kParameterCount>;

// Per-particle neighbour lists (CSR) of moving particles; any particle may be a neighbour.
struct Neighbours {
  std::vector<std::int32_t> start;  // size n + 1; particle i's list is [start[i], start[i+1])
  std::vector<std::int32_t> index;
};

struct Bond {
  std::int32_t particle, partner;
  double rest_cu;
  int type;    // 0: between two worm-body particles, 1: other
  int muscle;  // 1..96, or 0
};

// Constants and topology of a scene (everything that is not differentiated).
template <typename T>
struct Setup {
  // Hash cells (of h + skin) of the fixed particles, built once: they never move.
  using Cells = std::unordered_map<std::int64_t, std::vector<std::int32_t>>;
  std::shared_ptr<const Cells> fixed_cells;
  std::size_t n = 0;
  std::vector<char> moving;          // 1: moving, 0: fixed (boundary)
  std::vector<std::int32_t> movers;  // indices of the moving particles
  std::vector<std::int32_t> slot;    // a particle's index in movers, −1 for a fixed one
  std::vector<float> type;           // Sibernetic type codes
  std::vector<Bond> bonds;           // in file order (Gauss-Seidel order)
  std::vector<float> activation;     // muscle activations (96), held for the window
  // dt: one substep's length, the step's dt/substeps; every kernel but the forces (evaluated
  // once per step) works on substeps.
  T dt = 2e-5, s = 7.4e-6, mass = 2e-12;
  int substeps = 1;
  // The split step (xpbd_density_passes = m > 0, the run's default, xpbd.hpp): m passes of
  // `substeps` bond substeps of dt each, then one correction of correction_dt = m·… = the step/m
  // (density constraints, box, velocity correction). m = 0: `substeps` full substeps of dt.
  int density_passes = 0;
  T correction_dt = 0;
  T h = 3.34, poly6_cu = 0, spiky_cu = 0;  // density constraint kernels, cu
  T hs = 0, hs2 = 0, poly6_m = 0;          // SPH density, metres
  T viscosity_beta = 0;  // 1.5·m·(−∇Wspiky coefficient)/1000 (sphFluid.cl:657)
  T cohesion_gamma = 0;  // Sibernetic's surface_tension/m (cu offsets)
  T gravity[3] = {0, -9.8, 0};
  T r0 = 1.67;
  // Lists hold pairs within h + skin at the step's start: the projections evaluate kernels at
  // the predicted and projected positions, and a pair outside the list must stay beyond h
  // there, or list membership (decided at x) would make the step jump.
  T neighbour_skin = 1.0;
  T low[3] = {0, 0, 0}, high[3] = {0, 0, 0};  // box; low[1] is replaced by the floor parameter
  T bond_compliance_scale = 1;
  int iterations = 4;
  bool viscosity = true, surface_tension = true;
};

// Sibernetic's pair viscosity coefficient: 1e-5 between worm body and agar, 1e-4 otherwise.
inline double PairViscosity(float ti, float tj) {
  auto body = [](float t) { return t > 2.05f && t < 2.25f; };
  auto agar = [](float t) { return t > 2.25f && t < 2.35f; };
  return (body(ti) && agar(tj)) || (agar(ti) && body(tj)) ? 1.0e-5 : 1.0e-4;
}

template <typename T>
Vec3<T> Sub(const Vec3<T>& a, const Vec3<T>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <typename T>
T Dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <typename T>
void Axpy(T a, const Vec3<T>& x, Vec3<T>* y) {
  for (int c = 0; c < 3; ++c) (*y)[c] += a * x[c];
}

// ---- SPH density ----
// ρ_i = m·poly6·Σ_{j ∈ N(i) ∪ {i}} (hS² − s²|d_ij|²)³, d_ij = x_i − x_j (cu), pairs with
// s|d| < hS. Used by the viscosity's 1/ρ_i.
template <typename T>
void SphDensity(const Setup<T>& S, const Neighbours& nb, const Field<T>& x, std::vector<T>* rho) {
  rho->assign(S.n, T(0));
  const T c = S.mass * S.poly6_m, s2 = S.s * S.s;
  for (std::int32_t i : S.movers) {
    T sum = S.hs2 * S.hs2 * S.hs2;
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const Vec3<T> d = Sub(x[i], x[nb.index[m]]);
      const T q = S.hs2 - s2 * Dot(d, d);
      if (q > 0) sum += q * q * q;
    }
    (*rho)[i] = c * sum;
  }
}
// ∂ρ_i/∂d_ij = c·3q²·(−2s²d) with q = hS² − s²|d|²; d_ij = x_i − x_j gives +x̄_i, −x̄_j.
template <typename T>
void SphDensityBackward(const Setup<T>& S, const Neighbours& nb, const Field<T>& x,
                        const std::vector<T>& rho_bar, Field<T>* x_bar) {
  const T c = S.mass * S.poly6_m, s2 = S.s * S.s;
  for (std::int32_t i : S.movers) {
    if (rho_bar[i] == 0) continue;
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const std::int32_t j = nb.index[m];
      const Vec3<T> d = Sub(x[i], x[j]);
      const T q = S.hs2 - s2 * Dot(d, d);
      if (!(q > 0)) continue;
      const T f = rho_bar[i] * c * T(3) * q * q * T(-2) * s2;
      Axpy(f, d, &(*x_bar)[i]);
      Axpy(-f, d, &(*x_bar)[j]);
    }
  }
}

// ---- Interleaved forces: gravity + viscosity + cohesion (Sibernetic's, in double) ----
// a_i = g + β·μ/ρ_i·Σ_j c_ij (v_j − v_i)(hS − r) + γ·Σ_j (hS² − r²)³ d_ij,
// r = s|d_ij| < hS, c_ij Sibernetic's pair coefficient, μ the viscosity multiplier, a fixed
// neighbour's velocity zero.
template <typename T>
void Forces(const Setup<T>& S, const Neighbours& nb, const Field<T>& x, const Field<T>& v,
            const std::vector<T>& rho, T mu, Field<T>* a) {
  a->assign(S.n, Vec3<T>{0, 0, 0});
  const T s2 = S.s * S.s;
  for (std::int32_t i : S.movers) {
    Vec3<T> visc{0, 0, 0}, coh{0, 0, 0};
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const std::int32_t j = nb.index[m];
      const Vec3<T> d = Sub(x[i], x[j]);
      const T r2 = s2 * Dot(d, d);
      if (!(r2 < S.hs2)) continue;
      const T r = std::sqrt(r2);
      const Vec3<T> vj = S.moving[j] ? v[j] : Vec3<T>{0, 0, 0};
      if (S.viscosity)
        Axpy(T(PairViscosity(S.type[i], S.type[j])) * (S.hs - r), Sub(vj, v[i]), &visc);
      if (S.surface_tension) {
        const T q = S.hs2 - r2;
        Axpy(q * q * q, d, &coh);
      }
    }
    for (int c = 0; c < 3; ++c)
      (*a)[i][c] =
          S.gravity[c] + S.viscosity_beta * mu / rho[i] * visc[c] + S.cohesion_gamma * coh[c];
  }
}
// With V_i = Σ_j c(v_j − v_i)ℓ, ℓ = hS − r: ∂a/∂μ = βV/ρ, ∂a/∂ρ = −βμV/ρ², ∂a/∂v_j = βμcℓ/ρ·I
// (−that for v_i), ∂a/∂d via ℓ: −βμc/ρ (v_j − v_i)⊗(s²d/r). Cohesion: ∂(q³d)/∂d = q³I +
// d⊗(−6s²q²d) (symmetric). d = x_i − x_j: x̄_i += d̄, x̄_j −= d̄.
template <typename T>
void ForcesBackward(const Setup<T>& S, const Neighbours& nb, const Field<T>& x, const Field<T>& v,
                    const std::vector<T>& rho, T mu, const Field<T>& a_bar, Field<T>* x_bar,
                    Field<T>* v_bar, std::vector<T>* rho_bar, T* mu_bar) {
  const T s2 = S.s * S.s;
  for (std::int32_t i : S.movers) {
    const Vec3<T>& ab = a_bar[i];
    const T scale = S.viscosity_beta * mu / rho[i];
    Vec3<T> visc{0, 0, 0};
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const std::int32_t j = nb.index[m];
      const Vec3<T> d = Sub(x[i], x[j]);
      const T r2 = s2 * Dot(d, d);
      if (!(r2 < S.hs2)) continue;
      const T r = std::sqrt(r2);
      Vec3<T> d_bar{0, 0, 0};
      if (S.viscosity) {
        const T c = T(PairViscosity(S.type[i], S.type[j]));
        const Vec3<T> vj = S.moving[j] ? v[j] : Vec3<T>{0, 0, 0};
        const Vec3<T> dv = Sub(vj, v[i]);
        Axpy(c * (S.hs - r), dv, &visc);
        const T w = scale * c * (S.hs - r);
        if (S.moving[j]) Axpy(w, ab, &(*v_bar)[j]);
        Axpy(-w, ab, &(*v_bar)[i]);
        if (r > 0) Axpy(-scale * c * Dot(ab, dv) * s2 / r, d, &d_bar);
      }
      if (S.surface_tension) {
        const T q = S.hs2 - r2;
        Axpy(S.cohesion_gamma * q * q * q, ab, &d_bar);
        Axpy(S.cohesion_gamma * T(-6) * s2 * q * q * Dot(d, ab), d, &d_bar);
      }
      Axpy(T(1), d_bar, &(*x_bar)[i]);
      Axpy(T(-1), d_bar, &(*x_bar)[j]);
    }
    const T va = Dot(visc, ab);
    *mu_bar += S.viscosity_beta / rho[i] * va;
    (*rho_bar)[i] += -S.viscosity_beta * mu / (rho[i] * rho[i]) * va;
  }
}

// ---- Prediction: p = x + dt·(v + dt·a)/s (moving particles; fixed ones p = x) ----
// fixed_too = false leaves p's fixed entries as they are: a step's substeps keep them equal to
// x (fixed particles never move) instead of copying every particle per substep.
template <typename T>
void Predict(const Setup<T>& S, const Field<T>& x, const Field<T>& v, const Field<T>& a,
             Field<T>* p, bool fixed_too = true) {
  if (fixed_too || p->size() != S.n) *p = x;
  for (std::int32_t i : S.movers)
    for (int c = 0; c < 3; ++c) (*p)[i][c] = x[i][c] + S.dt * (v[i][c] + S.dt * a[i][c]) / S.s;
}
// Linear: x̄ += p̄, v̄ += p̄·dt/s, ā += p̄·dt²/s (a fixed particle: x̄ += p̄ only, left to the
// caller when fixed_too = false).
template <typename T>
void PredictBackward(const Setup<T>& S, const Field<T>& p_bar, Field<T>* x_bar, Field<T>* v_bar,
                     Field<T>* a_bar, bool fixed_too = true) {
  if (fixed_too)
    for (std::size_t i = 0; i < S.n; ++i)
      if (!S.moving[i]) Axpy(T(1), p_bar[i], &(*x_bar)[i]);
  for (std::int32_t i : S.movers)
    for (int c = 0; c < 3; ++c) {
      (*x_bar)[i][c] += p_bar[i][c];
      (*v_bar)[i][c] += p_bar[i][c] * S.dt / S.s;
      (*a_bar)[i][c] += p_bar[i][c] * S.dt * S.dt / S.s;
    }
}

// One neighbour pair's geometry, d = p_i − p_j, |d|², |d| and f(|d|), shared by a backward's
// loops over the pairs.
template <typename T>
struct PairGeometry {
  Vec3<T> d;
  T r2, r, f;
};

// ---- Density constraints, one Jacobi pass [MM13 eqs. 9-12] with XPBD's compliance ----
// C_i = V0·(W(0) + Σ_j W(|d_ij|²)) − 1, g_ij = V0·G(d_ij) = ∇_{p_i}C_i's share of j,
// D_i = Σ_{j moving}|g_ij|² + |Σ_j g_ij|² + α̃, Δλ_i = (−C_i − α̃λ_i)/D_i, λ_i += Δλ_i,
// p_i += Σ_j (Δλ_i + [j moving]Δλ_j)·g_ij. V0 = m/(ρ_rest s³), α̃ = α/dt².
template <typename T>
struct DensityTerms {
  T W(T r2) const {
    T q = h2 - r2;
    return r2 < h2 ? poly6 * q * q * q : T(0);
  }
  // −6·poly6·(h² − r²)², the factor of d in ∂W(|d|²)/∂d.
  T dW(T r2) const {
    T q = h2 - r2;
    return r2 < h2 ? T(-6) * poly6 * q * q : T(0);
  }
  // G(d) = σ(h − r)²/r·d = f(r)·d for 0 < r < h.
  T f(T r) const { return r > 0 && r < h ? spiky * (h - r) * (h - r) / r : T(0); }
  // f'(r) = σ(−2(h − r)/r − (h − r)²/r²).
  T df(T r) const {
    return r > 0 && r < h ? spiky * (T(-2) * (h - r) / r - (h - r) * (h - r) / (r * r)) : T(0);
  }
  T h, h2, poly6, spiky;
};
template <typename T>
DensityTerms<T> TermsOf(const Setup<T>& S) {
  return {S.h, S.h * S.h, S.poly6_cu, S.spiky_cu};
}

// Δλ of every moving particle from p and λ (the first half of the pass). Outputs indexed by
// particle; a fixed particle's entries are zero when the vectors are sized here, and never read.
template <typename T>
void DensityMultipliers(const Setup<T>& S, const Neighbours& nb, T V0, T at, const Field<T>& p,
                        const std::vector<T>& lambda, std::vector<T>* dlambda,
                        std::vector<T>* denominator) {
  const DensityTerms<T> K = TermsOf(S);
  if (dlambda->size() != S.n) dlambda->assign(S.n, T(0));
  if (denominator->size() != S.n) denominator->assign(S.n, T(0));
  for (std::int32_t i : S.movers) {
    T w = K.W(0), norm2 = 0;
    Vec3<T> gi{0, 0, 0};
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const std::int32_t j = nb.index[m];
      const Vec3<T> d = Sub(p[i], p[j]);
      const T r2 = Dot(d, d);
      w += K.W(r2);
      const T g = V0 * K.f(std::sqrt(r2));
      Axpy(g, d, &gi);
      if (S.moving[j]) norm2 += g * g * r2;
    }
    const T D = norm2 + Dot(gi, gi) + at;
    (*denominator)[i] = D;
    (*dlambda)[i] = D > 0 ? (-(V0 * w - 1) - at * lambda[i]) / D : T(0);
  }
}

// Keeps Δλ and the denominators in `record` when given (a tape's, for the backward).
template <typename T>
void DensityPass(const Setup<T>& S, const Neighbours& nb, T V0, T at, Field<T>* p,
                 std::vector<T>* lambda, std::array<std::vector<T>, 2>* record = nullptr) {
  const DensityTerms<T> K = TermsOf(S);
  std::array<std::vector<T>, 2> local;
  std::array<std::vector<T>, 2>& r = record ? *record : local;
  DensityMultipliers(S, nb, V0, at, *p, *lambda, &r[0], &r[1]);
  const std::vector<T>& dl = r[0];
  Field<T> dp(S.movers.size(), Vec3<T>{0, 0, 0});  // by index in movers
  for (std::size_t k = 0; k < S.movers.size(); ++k) {
    const std::int32_t i = S.movers[k];
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const std::int32_t j = nb.index[m];
      const Vec3<T> d = Sub((*p)[i], (*p)[j]);
      Axpy((dl[i] + (S.moving[j] ? dl[j] : T(0))) * V0 * K.f(std::sqrt(Dot(d, d))), d, &dp[k]);
    }
  }
  for (std::size_t k = 0; k < S.movers.size(); ++k) {
    const std::int32_t i = S.movers[k];
    (*lambda)[i] += dl[i];
    for (int c = 0; c < 3; ++c) (*p)[i][c] += dp[k][c];
  }
}

// Backward of DensityPass at its input (p, λ): p_bar and lambda_bar hold the output cotangents
// on entry and the input cotangents on exit. Reverse of the forward:
//   Δp_i = Σ_j (Δλ_i + Δλ_j)g_ij: Δλ̄_i += p̄_i·g_ij, Δλ̄_j += p̄_i·g_ij, ḡ_ij = (Δλ_i + Δλ_j)p̄_i;
//   λ' = λ + Δλ: Δλ̄ += λ̄'; Δλ = (−C − α̃λ)/D: C̄ = −Δλ̄/D, λ̄ += −α̃Δλ̄/D, D̄ = −Δλ̄Δλ/D,
//   ᾱ̃ += −λΔλ̄/D + D̄; D: ḡ_ij += 2D̄([j moving]g_ij + g_i); C = V0·w − 1: V̄0 += C̄w,
//   p̄ via ∂W/∂d; g_ij = V0 f(r) d: V̄0 += f(r)(ḡ·d), d̄ = V0(f ḡ + f'(r)(d·ḡ)d/r).
// `record`: the forward's Δλ and denominators when kept, else recomputed here.
template <typename T>
void DensityPassBackward(const Setup<T>& S, const Neighbours& nb, T V0, T at, const Field<T>& p,
                         const std::vector<T>& lambda, Field<T>* p_bar, std::vector<T>* lambda_bar,
                         T* V0_bar, T* at_bar,
                         const std::array<std::vector<T>, 2>* record = nullptr) {
  const DensityTerms<T> K = TermsOf(S);
  std::array<std::vector<T>, 2> local;
  if (!record) DensityMultipliers(S, nb, V0, at, p, lambda, &local[0], &local[1]);
  const std::vector<T>& dl = record ? (*record)[0] : local[0];
  const std::vector<T>& D = record ? (*record)[1] : local[1];
  // By index in movers (S.slot): the cotangent of p' (p' = p + Δp: p̄ starts as p̄'), and Δλ̄.
  const std::size_t movers = S.movers.size();
  Field<T> pb_out(movers);
  std::vector<T> dl_bar(movers);
  for (std::size_t k = 0; k < movers; ++k) {
    pb_out[k] = (*p_bar)[S.movers[k]];
    dl_bar[k] = (*lambda_bar)[S.movers[k]];
  }
  // Each pair's d, |d|² and |d| once (the three loops below need the same values).
  std::vector<PairGeometry<T>> pair(nb.index.size());
  for (std::int32_t i : S.movers)
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      PairGeometry<T>& g = pair[std::size_t(m)];
      g.d = Sub(p[i], p[nb.index[m]]);
      g.r2 = Dot(g.d, g.d);
      g.r = std::sqrt(g.r2);
      g.f = K.f(g.r);
    }
  // Δp terms: the Δλ cotangents first (they feed C̄, D̄ below).
  for (std::size_t k = 0; k < movers; ++k) {
    const std::int32_t i = S.movers[k];
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const std::int32_t j = nb.index[m];
      const PairGeometry<T>& g = pair[std::size_t(m)];
      const T pg = V0 * g.f * Dot(pb_out[k], g.d);
      dl_bar[k] += pg;
      if (S.moving[j]) dl_bar[std::size_t(S.slot[j])] += pg;
    }
  }
  for (std::size_t k = 0; k < movers; ++k) {
    const std::int32_t i = S.movers[k];
    const T Di = D[i];
    T C_bar = 0, D_bar = 0;
    if (Di > 0) {
      C_bar = -dl_bar[k] / Di;
      (*lambda_bar)[i] += -at * dl_bar[k] / Di;
      D_bar = -dl_bar[k] * dl[i] / Di;
      *at_bar += -lambda[i] * dl_bar[k] / Di + D_bar;
    }
    Vec3<T> gi{0, 0, 0};
    T w = K.W(0);
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const PairGeometry<T>& g = pair[std::size_t(m)];
      w += K.W(g.r2);
      Axpy(V0 * g.f, g.d, &gi);
    }
    *V0_bar += C_bar * w;
    for (std::int32_t m = nb.start[i]; m < nb.start[i + 1]; ++m) {
      const std::int32_t j = nb.index[m];
      const Vec3<T>& d = pair[std::size_t(m)].d;
      const T r2 = pair[std::size_t(m)].r2, r = pair[std::size_t(m)].r, f = pair[std::size_t(m)].f;
      const T g = V0 * f;
      // ḡ_ij: from Δp_i and from D_i.
      Vec3<T> gb{0, 0, 0};
      Axpy(dl[i] + (S.moving[j] ? dl[j] : T(0)), pb_out[k], &gb);
      Axpy(T(2) * D_bar, gi, &gb);
      if (S.moving[j]) Axpy(T(2) * D_bar * g, d, &gb);
      *V0_bar += f * Dot(gb, d);
      Vec3<T> db{0, 0, 0};
      Axpy(V0 * f, gb, &db);
      if (r > 0) Axpy(V0 * K.df(r) * Dot(d, gb) / r, d, &db);
      Axpy(C_bar * V0 * K.dW(r2), d, &db);  // from C_i's W terms
      Axpy(T(1), db, &(*p_bar)[i]);
      Axpy(T(-1), db, &(*p_bar)[j]);
    }
  }
}

// ---- Bonds, one Gauss-Seidel pass in file order [MMC16 eqs. 17-18], one-sided (w_a = 1,
// w_b = 0, as xpbd.cpp's ProjectBonds): k = k_type·(1 + activation·strength) for a muscle
// bond with activation > 0, α̃ = scale/(k dt²), C = |p_a − p_b| − L0, Δλ = (−C − α̃λ)/(1 + α̃),
// p_a += Δλ·n. ----
template <typename T>
T BondStiffness(const Setup<T>& S, const Bond& b, const Parameters<T>& theta) {
  T k = b.type == 0 ? theta[kBondStiffnessBody] : theta[kBondStiffnessOther];
  if (b.muscle >= 1 && b.muscle <= int(S.activation.size()) && S.activation[b.muscle - 1] > 0)
    k *= T(1) + T(S.activation[b.muscle - 1]) * theta[kMuscleStrength];
  return k;
}

template <typename T>
void BondPass(const Setup<T>& S, const Parameters<T>& theta, Field<T>* p, std::vector<T>* lambda,
              std::vector<Vec3<T>>* partner_record = nullptr,
              std::vector<Vec3<T>>* particle_record = nullptr) {
  for (std::size_t b = 0; b < S.bonds.size(); ++b) {
    const Bond& bond = S.bonds[b];
    if (particle_record) {
      (*particle_record)[b] = (*p)[bond.particle];
      (*partner_record)[b] = (*p)[bond.partner];
    }
    const T k = BondStiffness(S, bond, theta);
    if (!(k > 0)) continue;
    Vec3<T> partner = (*p)[bond.partner];
    ProjectDistance(&(*p)[bond.particle], &partner, T(1), T(0), T(bond.rest_cu),
                    S.bond_compliance_scale / (k * S.dt * S.dt), &(*lambda)[b]);
  }
}

// One bond's backward, shared by the Gauss-Seidel and the Jacobi pass (the derivation above
// BondPassBackward): bond b read its particle at pa and its partner at pb, with multiplier lam;
// pa_bar is the cotangent of its particle's position after it. Adds d̄ to both ends' p̄, maps
// λ̄_b in place and adds k̄ to θ̄.
template <typename T>
void BondBackward(const Setup<T>& S, const Parameters<T>& theta, std::size_t b, const Vec3<T>& pa,
                  const Vec3<T>& pb, T lam, const Vec3<T> pa_bar, Field<T>* p_bar,
                  std::vector<T>* lambda_bar, Parameters<T>* theta_bar) {
  const Bond& bond = S.bonds[b];
  const T k = BondStiffness(S, bond, theta);
  if (!(k > 0)) return;
  const T at = S.bond_compliance_scale / (k * S.dt * S.dt), D = T(1) + at;
  const Vec3<T> d = Sub(pa, pb);
  const T L = std::sqrt(Dot(d, d));
  if (!(L > 0)) return;
  const T dl = (-(L - T(bond.rest_cu)) - at * lam) / D;
  const Vec3<T> n{d[0] / L, d[1] / L, d[2] / L};
  const T dl_bar = (*lambda_bar)[b] + Dot(pa_bar, n);
  const Vec3<T> n_bar{dl * pa_bar[0], dl * pa_bar[1], dl * pa_bar[2]};
  const T C_bar = -dl_bar / D;
  (*lambda_bar)[b] += -at * dl_bar / D;
  const T at_bar = -dl_bar * (lam + dl) / D;
  const T nn = Dot(n_bar, n);
  Vec3<T> d_bar;
  for (int c = 0; c < 3; ++c) d_bar[c] = C_bar * n[c] + (n_bar[c] - nn * n[c]) / L;
  Axpy(T(1), d_bar, &(*p_bar)[bond.particle]);
  Axpy(T(-1), d_bar, &(*p_bar)[bond.partner]);
  const T k_bar = -at_bar * at / k;
  const T k_type = bond.type == 0 ? theta[kBondStiffnessBody] : theta[kBondStiffnessOther];
  const T factor = k / k_type;
  (*theta_bar)[bond.type == 0 ? kBondStiffnessBody : kBondStiffnessOther] += k_bar * factor;
  if (factor != T(1))
    (*theta_bar)[kMuscleStrength] += k_bar * k_type * T(S.activation[bond.muscle - 1]);
}

// Backward of BondPass (p_bar, lambda_bar: output cotangents in, input cotangents out): the
// forward is re-run to record each bond's input positions, then the bonds are reversed. For
// one bond, n = d/L, d = p_a − p_b, D = 1 + α̃:
//   p_a' = p_a + Δλn: Δλ̄ = λ̄' + p̄_a'·n, n̄ = Δλp̄_a';  Δλ = (−C − α̃λ)/D: C̄ = −Δλ̄/D,
//   λ̄ = λ̄' − α̃Δλ̄/D, ᾱ̃ = −Δλ̄(λ + Δλ)/D;  d̄ = C̄n + (n̄ − (n̄·n)n)/L, p̄_a += d̄, p̄_b −= d̄;
//   α̃ = scale/(k dt²): k̄ = −ᾱ̃α̃/k; k = k_type(1 + a·σ): k̄_type += k̄(1 + aσ), σ̄ += k̄·k_type·a.
// `partners`, `particles`: the forward's recorded bond ends when kept, else re-recorded here.
template <typename T>
void BondPassBackward(const Setup<T>& S, const Parameters<T>& theta, const Field<T>& p,
                      const std::vector<T>& lambda, Field<T>* p_bar, std::vector<T>* lambda_bar,
                      Parameters<T>* theta_bar, const std::vector<Vec3<T>>* partners = nullptr,
                      const std::vector<Vec3<T>>* particles = nullptr) {
  const std::size_t nb = S.bonds.size();
  std::vector<Vec3<T>> local_a, local_b;
  if (!partners) {
    local_a.resize(nb), local_b.resize(nb);
    Field<T> q = p;
    std::vector<T> l = lambda;
    BondPass(S, theta, &q, &l, &local_b, &local_a);
  }
  const std::vector<Vec3<T>>& pa = particles ? *particles : local_a;
  const std::vector<Vec3<T>>& pb = partners ? *partners : local_b;
  // λ before each bond is the pass's input: λ_b is touched only by bond b, once per pass.
  for (std::size_t b = nb; b-- > 0;)
    BondBackward(S, theta, b, pa[b], pb[b], lambda[b], (*p_bar)[S.bonds[b].particle], p_bar,
                 lambda_bar, theta_bar);
}

// ---- Bonds of the split step: one Jacobi pass of one-sided distance constraints ----
// Every bond reads both ends as the pass began (s), and its row's particle moves by the sum of
// its bonds' corrections: p_a = s_a + Σ_b Δλ_b·n_b, n_b = d_b/L_b, d_b = s_a − s_q,
// Δλ_b = (−(L_b − r_b) − α̃_b λ_b)/(1 + α̃_b), λ_b += Δλ_b, α̃_b = scale/(k_b dt²)
// (Xpbd::ProjectBondsOneSided). The records, when given, receive each bond's s_a (particles) and
// s_q (partners).
template <typename T>
void BondPassJacobi(const Setup<T>& S, const Parameters<T>& theta, Field<T>* p,
                    std::vector<T>* lambda, std::vector<Vec3<T>>* partner_record = nullptr,
                    std::vector<Vec3<T>>* particle_record = nullptr) {
  const Field<T> start = *p;
  Field<T> sum(S.n, Vec3<T>{0, 0, 0});  // summed apart, then added: the run's rounding
  for (std::size_t b = 0; b < S.bonds.size(); ++b) {
    const Bond& bond = S.bonds[b];
    const Vec3<T>&sa = start[bond.particle], &sq = start[bond.partner];
    if (particle_record) (*particle_record)[b] = sa, (*partner_record)[b] = sq;
    const T k = BondStiffness(S, bond, theta);
    if (!(k > 0)) continue;
    const Vec3<T> d = Sub(sa, sq);
    const T L = std::sqrt(Dot(d, d));
    if (!(L > 0)) continue;
    const T at = S.bond_compliance_scale / (k * S.dt * S.dt);
    const T dl = (-(L - T(bond.rest_cu)) - at * (*lambda)[b]) / (T(1) + at);
    (*lambda)[b] += dl;
    Axpy(dl / L, d, &sum[bond.particle]);
  }
  for (std::size_t b = 0; b < S.bonds.size(); ++b)  // each row's particle once
    if (b == 0 || S.bonds[b].particle != S.bonds[b - 1].particle)
      for (int c = 0; c < 3; ++c) (*p)[S.bonds[b].particle][c] += sum[S.bonds[b].particle][c];
}
// Backward (p_bar, lambda_bar: output cotangents in, input cotangents out). p_a = s_a + Σ
// passes p̄ to s̄ unchanged; each bond then adds its BondBackward from the OUTPUT cotangent p̄_a
// (read before any bond's contribution is added), with λ the pass's input.
template <typename T>
void BondPassJacobiBackward(const Setup<T>& S, const Parameters<T>& theta,
                            const std::vector<T>& lambda, const std::vector<Vec3<T>>& particles,
                            const std::vector<Vec3<T>>& partners, Field<T>* p_bar,
                            std::vector<T>* lambda_bar, Parameters<T>* theta_bar) {
  const Field<T> out_bar = *p_bar;
  for (std::size_t b = 0; b < S.bonds.size(); ++b)
    BondBackward(S, theta, b, particles[b], partners[b], lambda[b], out_bar[S.bonds[b].particle],
                 p_bar, lambda_bar, theta_bar);
}

// ---- Box: p clamped into [low, high], the floor parameter as low y ----
template <typename T>
void BoxPass(const Setup<T>& S, T floor, Field<T>* p) {
  const T low[3] = {S.low[0], floor, S.low[2]};
  for (std::int32_t i : S.movers)
    for (int c = 0; c < 3; ++c) (*p)[i][c] = std::clamp((*p)[i][c], low[c], S.high[c]);
}
// A clamped component's output is a bound: its cotangent goes to the bound (the floor's, for
// low y), not to p.
template <typename T>
void BoxPassBackward(const Setup<T>& S, T floor, const Field<T>& p, Field<T>* p_bar, T* floor_bar) {
  const T low[3] = {S.low[0], floor, S.low[2]};
  for (std::int32_t i : S.movers)
    for (int c = 0; c < 3; ++c) {
      if (p[i][c] < low[c]) {
        if (c == 1) *floor_bar += (*p_bar)[i][c];
        (*p_bar)[i][c] = 0;
      } else if (p[i][c] > S.high[c]) {
        (*p_bar)[i][c] = 0;
      }
    }
}

// ---- Velocity update: v = (p − x)s/dt; within r0 of the floor a downward v_y becomes
// −e·v_y; x' = p ----
// fixed_too = false leaves the fixed entries of v (zero) and x' (= p) as they are.
template <typename T>
void UpdateVelocity(const Setup<T>& S, T floor, T e, const Field<T>& x, const Field<T>& p,
                    Field<T>* v, Field<T>* x_next, bool fixed_too = true) {
  if (fixed_too || v->size() != S.n) v->assign(S.n, Vec3<T>{0, 0, 0});
  if (fixed_too || x_next->size() != S.n) *x_next = p;
  for (std::int32_t i : S.movers) {  // x_next may be x itself: x[i] is read before it is set
    for (int c = 0; c < 3; ++c) (*v)[i][c] = (p[i][c] - x[i][c]) * S.s / S.dt;
    if (p[i][1] <= floor + S.r0 && (*v)[i][1] < 0) (*v)[i][1] = -e * (*v)[i][1];
    (*x_next)[i] = p[i];
  }
}
// v̄_pre = v̄ except a restituted y: v̄_pre = −e·v̄, ē += −v_pre·v̄; p̄ += v̄_pre s/dt + x̄',
// x̄ += −v̄_pre s/dt. (The floor test is a switch: its position is held constant.) A fixed
// particle's p̄ += x̄' is left to the caller when fixed_too = false.
template <typename T>
void UpdateVelocityBackward(const Setup<T>& S, T floor, T e, const Field<T>& x, const Field<T>& p,
                            const Field<T>& v_bar, const Field<T>& x_next_bar, Field<T>* x_bar,
                            Field<T>* p_bar, T* e_bar, bool fixed_too = true) {
  if (fixed_too)
    for (std::size_t i = 0; i < S.n; ++i)  // a fixed particle: x' = p, v' = 0
      if (!S.moving[i]) Axpy(T(1), x_next_bar[i], &(*p_bar)[i]);
  for (std::int32_t i : S.movers) {
    Vec3<T> vb = v_bar[i];
    const T vy = (p[i][1] - x[i][1]) * S.s / S.dt;
    if (p[i][1] <= floor + S.r0 && vy < 0) {
      *e_bar += -vy * vb[1];
      vb[1] = -e * vb[1];
    }
    for (int c = 0; c < 3; ++c) {
      (*p_bar)[i][c] += vb[c] * S.s / S.dt + x_next_bar[i][c];
      (*x_bar)[i][c] += -vb[c] * S.s / S.dt;
    }
  }
}

// ---- The split step's velocity correction over H: u = v + (p − x)s/H; within r0 of the floor a
// downward u_y becomes −e·u_y; v' = u, x' = p (Xpbd::Correct without the wall particles) ----
template <typename T>
void CorrectVelocity(const Setup<T>& S, T H, T floor, T e, const Field<T>& x, const Field<T>& p,
                     Field<T>* v, Field<T>* x_next) {
  for (std::int32_t i : S.movers) {  // x_next may be x itself: x[i] is read before it is set
    for (int c = 0; c < 3; ++c) (*v)[i][c] += (p[i][c] - x[i][c]) * S.s / H;
    if (p[i][1] <= floor + S.r0 && (*v)[i][1] < 0) (*v)[i][1] = -e * (*v)[i][1];
    (*x_next)[i] = p[i];
  }
}
// v_in is the input velocity. ū = v̄' except a restituted y: ū_y = −e·v̄'_y, ē += −u_y·v̄'_y;
// v̄_in = ū, p̄ += ū s/H + x̄', x̄ += −ū s/H (moving particles; the floor test is a switch).
template <typename T>
void CorrectVelocityBackward(const Setup<T>& S, T H, T floor, T e, const Field<T>& x,
                             const Field<T>& p, const Field<T>& v_in, const Field<T>& v_bar,
                             const Field<T>& x_next_bar, Field<T>* x_bar, Field<T>* v_in_bar,
                             Field<T>* p_bar, T* e_bar) {
  for (std::int32_t i : S.movers) {
    Vec3<T> ub = v_bar[i];
    const T uy = v_in[i][1] + (p[i][1] - x[i][1]) * S.s / H;
    if (p[i][1] <= floor + S.r0 && uy < 0) {
      *e_bar += -uy * ub[1];
      ub[1] = -e * ub[1];
    }
    for (int c = 0; c < 3; ++c) {
      (*v_in_bar)[i][c] += ub[c];
      (*p_bar)[i][c] += ub[c] * S.s / H + x_next_bar[i][c];
      (*x_bar)[i][c] += -ub[c] * S.s / H;
    }
  }
}

}  // namespace owval::engine::internal::adjoint
