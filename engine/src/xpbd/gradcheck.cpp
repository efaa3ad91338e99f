// `owval gradcheck`: every backward kernel of adjoint.hpp, one whole step, and a multi-step
// reverse pass against central differences in double. For a kernel f with VJP f̄ and random
// direction d (scaled per input: positions by 1 cu (0.1 cu in the force kernel and the whole
// step), velocities by 0.05 m/s, parameters by their own magnitude) and random output cotangent u:
//   finite difference  u·(f(z + εd) − f(z − εd))/(2ε),   analytic  f̄(z; u)·d,
// relative error |fd − an|/max(|fd|, |an|), or |fd − an| when either is exactly 0. Each kernel
// runs at ε = 1e-3 (DD001's) and at its own ε.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/engine/gradient.hpp"
#include "xpbd/differentiable.hpp"

namespace owval::engine {
namespace {

namespace ad = internal::adjoint;
using ad::Field;
using ad::Parameters;
using Vector = std::vector<double>;

// |fd − an| over the larger magnitude; the absolute difference when either is exactly zero, where
// a ratio means nothing (as Ceres' GradientChecker compares). A loss at its minimum has an
// exactly zero gradient wherever nothing moves it (free_fall's one particle under the
// self-referenced loss: no shifted parameter acts on it), against a quotient of rounding noise,
// 2e-13, whose ratio to itself would be 1.
double RelativeError(double finite_difference, double analytic) {
  const double difference = std::abs(finite_difference - analytic);
  if (finite_difference == 0 || analytic == 0) return difference;
  return difference / std::max(std::abs(finite_difference), std::abs(analytic));
}

struct KernelCheck {
  double epsilon;  // the kernel's own ε (besides 1e-3)
  Vector at, scale;
  std::function<Vector(const Vector&)> f;
  std::function<Vector(const Vector&, const Vector&)> vjp;
};

// Packing of fields and scalars into one vector.
void Put(const Field<double>& f, Vector* z) {
  for (const auto& a : f) z->insert(z->end(), a.begin(), a.end());
}
Field<double> TakeField(const Vector& z, std::size_t* at, std::size_t n) {
  Field<double> f(n);
  for (auto& a : f)
    for (double& c : a) c = z[(*at)++];
  return f;
}
Vector Take(const Vector& z, std::size_t* at, std::size_t n) {
  Vector v(z.begin() + std::ptrdiff_t(*at), z.begin() + std::ptrdiff_t(*at + n));
  *at += n;
  return v;
}
Parameters<double> TakeParameters(const Vector& z, std::size_t* at) {
  Parameters<double> t{};
  for (double& c : t) c = z[(*at)++];
  return t;
}

// A small scene touching every kernel: a jittered liquid block on a boundary layer, with some
// particles below the floor parameter; an elastic cube of body and agar particles bonded
// pairwise, one bond a muscle at half activation.
SiberneticConfig Scene(std::mt19937_64* rng) {
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), speed(-0.05, 0.05);
  SiberneticConfig c;
  c.source = "gradcheck scene";
  c.box = {0, 30, 0, 30, 0, 30};
  auto add = [&](double x, double y, double z, float type) {
    c.position.push_back({float(x), float(y), float(z), type});
    c.velocity.push_back(type == 3.0f
                             ? Row4{0, 1, 0, 0}
                             : Row4{float(speed(*rng)), float(speed(*rng)), float(speed(*rng)), 0});
  };
  const double e = 1.6;
  for (int i = 0; i < 8; ++i)
    add(20 + e * (i & 1) + jitter(*rng), 5 + e * ((i >> 1) & 1) + jitter(*rng),
        20 + e * (i >> 2) + jitter(*rng), i < 4 ? 2.1f : 2.3f);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k)
        add(10 + 1.5 * i + jitter(*rng), 2.2 + 1.5 * j + jitter(*rng), 10 + 1.5 * k + jitter(*rng),
            1.1f);
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 6; ++k) add(9 + 1.2 * i, 0.8, 9 + 1.2 * k, 3.0f);
  c.connection.assign(8 * kConnectionSlots, {-1, 0, 0, 0});
  for (int a = 0; a < 8; ++a) {
    int slot = 0;
    for (int b = 0; b < 8; ++b) {
      if (a == b) continue;
      const Row4 &pa = c.position[a], &pb = c.position[b];
      const double d = std::hypot(pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]);
      const float muscle = a == 0 && b == 1 ? 1.0f : 0.0f;
      c.connection[a * kConnectionSlots + slot++] = {float(b), float(1.05 * d), muscle, 0};
    }
  }
  c.particle_mem_index.assign(8 * kMembraneSlotsPerParticle, -1);
  return c;
}

struct SceneState {
  ad::Setup<double> S;
  Parameters<double> theta;
  Field<double> x, v;
  ad::Neighbours nb;
};

// The smallest | |x_i − x_j| − h | over the pairs of a moving particle: the viscosity kernel
// (hS − r) has a kink at h, where no derivative exists for a difference quotient to approach.
double DistanceToKink(const SiberneticConfig& c, double h) {
  double closest = 1e300;
  for (std::size_t i = 0; i < c.position.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      if (c.position[i][3] == 3.0f && c.position[j][3] == 3.0f) continue;
      const Row4 &a = c.position[i], &b = c.position[j];
      closest = std::min(closest, std::abs(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) - h));
    }
  return closest;
}

SceneState MakeScene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  SiberneticConfig c = Scene(&rng);
  // Random draws until no pair sits within 0.02 cu of the kink (a few draws on average).
  for (int draw = 0; draw < 1000 && DistanceToKink(c, PhysicsConstants{}.h_cu) < 0.02; ++draw)
    c = Scene(&rng);
  PhysicsConstants constants;
  SceneState s{ad::SetupOf(c, constants), {}, {}, {}, {}};
  s.S.activation[0] = 0.5f;
  s.theta = {1000.0, 3e8, 7.5e7, 1.0, 4e-11, 2.6, 0.5, 1.0};
  for (std::size_t i = 0; i < s.S.n; ++i) {
    s.x.push_back({c.position[i][0], c.position[i][1], c.position[i][2]});
    s.v.push_back(s.S.moving[i] ? Vec3d{c.velocity[i][0], c.velocity[i][1], c.velocity[i][2]}
                                : Vec3d{0, 0, 0});
  }
  s.nb = ad::FindNeighbours(s.S, s.x);
  return s;
}

Vector Ones(std::size_t n, double v) { return Vector(n, v); }
Vector ParameterScale(const Parameters<double>& t) {
  Vector s;
  for (double v : t) s.push_back(v != 0 ? std::abs(v) : 1.0);
  s[ad::kRestitution] = 0.1;
  return s;
}

KernelCheck SphDensityCheck(const SceneState& s) {
  KernelCheck k{1e-5, {}, Ones(3 * s.S.n, 0.1), {}, {}};
  Put(s.x, &k.at);
  k.f = [&s](const Vector& z) {
    std::size_t at = 0;
    Vector rho;
    ad::SphDensity(s.S, s.nb, TakeField(z, &at, s.S.n), &rho);
    return rho;
  };
  k.vjp = [&s](const Vector& z, const Vector& u) {
    std::size_t at = 0;
    Field<double> xb(s.S.n, Vec3d{0, 0, 0});
    ad::SphDensityBackward(s.S, s.nb, TakeField(z, &at, s.S.n), u, &xb);
    Vector out;
    Put(xb, &out);
    return out;
  };
  return k;
}

// The force kernel's inputs, unpacked from the checked vector: positions, velocities, densities
// and the viscosity multiplier μ.
struct ForcesInputs {
  Field<double> x, v;
  Vector rho;
  double mu;
};

ForcesInputs UnpackForces(std::size_t n, const Vector& z) {
  ForcesInputs in;
  std::size_t at = 0;
  in.x = TakeField(z, &at, n);
  in.v = TakeField(z, &at, n);
  in.rho = Take(z, &at, n);
  in.mu = z[at];
  return in;
}

Vector ForcesOutputs(const SceneState& s, const Vector& z) {
  const ForcesInputs in = UnpackForces(s.S.n, z);
  Field<double> a;
  ad::Forces(s.S, s.nb, in.x, in.v, in.rho, in.mu, &a);
  Vector out;
  Put(a, &out);
  return out;
}

Vector ForcesVjp(const SceneState& s, const Vector& z, const Vector& u) {
  const std::size_t n = s.S.n;
  const ForcesInputs in = UnpackForces(n, z);
  double mu_bar = 0;
  std::size_t at = 0;
  const Field<double> ab = TakeField(u, &at, n);
  Field<double> xb(n, Vec3d{0, 0, 0}), vb = xb;
  Vector rb(n, 0.0);
  ad::ForcesBackward(s.S, s.nb, in.x, in.v, in.rho, in.mu, ab, &xb, &vb, &rb, &mu_bar);
  Vector out;
  Put(xb, &out);
  Put(vb, &out);
  out.insert(out.end(), rb.begin(), rb.end());
  out.push_back(mu_bar);
  return out;
}

KernelCheck ForcesCheck(const SceneState& s) {
  const std::size_t n = s.S.n;
  KernelCheck k{1e-5, {}, {}, {}, {}};
  Vector rho;
  ad::SphDensity(s.S, s.nb, s.x, &rho);
  Put(s.x, &k.at);
  Put(s.v, &k.at);
  k.at.insert(k.at.end(), rho.begin(), rho.end());
  k.at.push_back(1.0);
  // Positions by 0.1 cu: the cohesion's (hS² − r²)³ bends sharply near r = h, where a 1 cu
  // direction's second-order term is no longer small at ε = 1e-3.
  k.scale = Ones(3 * n, 0.1);
  const Vector vs = Ones(3 * n, 0.05);
  k.scale.insert(k.scale.end(), vs.begin(), vs.end());
  for (double r : rho) k.scale.push_back(r > 0 ? r * 0.1 : 1.0);
  k.scale.push_back(1.0);
  k.f = [&s](const Vector& z) { return ForcesOutputs(s, z); };
  k.vjp = [&s](const Vector& z, const Vector& u) { return ForcesVjp(s, z, u); };
  return k;
}

KernelCheck PredictCheck(const SceneState& s) {
  const std::size_t n = s.S.n;
  KernelCheck k{1e-5, {}, Ones(3 * n, 0.1), {}, {}};
  Put(s.x, &k.at);
  Put(s.v, &k.at);
  Field<double> a(n, Vec3d{0, -9.8, 0});
  Put(a, &k.at);
  for (double v : Ones(3 * n, 0.05)) k.scale.push_back(v);
  for (double v : Ones(3 * n, 10.0)) k.scale.push_back(v);
  k.f = [&s, n](const Vector& z) {
    std::size_t at = 0;
    const Field<double> x = TakeField(z, &at, n), v = TakeField(z, &at, n),
                        a = TakeField(z, &at, n);
    Field<double> p;
    ad::Predict(s.S, x, v, a, &p);
    Vector out;
    Put(p, &out);
    return out;
  };
  k.vjp = [&s, n](const Vector&, const Vector& u) {
    std::size_t at = 0;
    Field<double> xb(n, Vec3d{0, 0, 0}), vb = xb, ab = xb;
    ad::PredictBackward(s.S, TakeField(u, &at, n), &xb, &vb, &ab);
    Vector out;
    Put(xb, &out);
    Put(vb, &out);
    Put(ab, &out);
    return out;
  };
  return k;
}

// The density pass's inputs, unpacked from the checked vector: positions, multipliers, and the
// rest volume V0 and compliance α̃ of the scene's parameters with ρ_rest and α_density from it.
struct DensityInputs {
  Field<double> p;
  Vector l;
  double V0, alpha_tilde;
};

DensityInputs UnpackDensity(const SceneState& s, const Vector& z) {
  const std::size_t n = s.S.n;
  DensityInputs in;
  std::size_t i = 0;
  in.p = TakeField(z, &i, n);
  in.l = Take(z, &i, n);
  Parameters<double> t = s.theta;
  t[ad::kRestDensity] = z[i];
  t[ad::kAlphaDensity] = z[i + 1];
  in.V0 = ad::RestVolume(s.S, t);
  in.alpha_tilde = ad::DensityAlphaTilde(s.S, t);
  return in;
}

Vector DensityOutputs(const SceneState& s, const Vector& z) {
  DensityInputs in = UnpackDensity(s, z);
  ad::DensityPass(s.S, s.nb, in.V0, in.alpha_tilde, &in.p, &in.l);
  Vector out;
  Put(in.p, &out);
  out.insert(out.end(), in.l.begin(), in.l.end());
  return out;
}

// The VJP in (positions, λ, ρ_rest, α_density): V0 = m/ρ_rest and α̃ = α_density/Δt² carry
// V0's and α̃'s cotangents to the parameters.
Vector DensityVjp(const SceneState& s, const Vector& z, const Vector& u) {
  const std::size_t n = s.S.n;
  const DensityInputs in = UnpackDensity(s, z);
  double V0_bar = 0, at_bar = 0;
  std::size_t i = 0;
  Field<double> pb = TakeField(u, &i, n);
  Vector lb = Take(u, &i, n);
  ad::DensityPassBackward(s.S, s.nb, in.V0, in.alpha_tilde, in.p, in.l, &pb, &lb, &V0_bar, &at_bar);
  Vector out;
  Put(pb, &out);
  out.insert(out.end(), lb.begin(), lb.end());
  const double rho = z[z.size() - 2];
  out.push_back(V0_bar * -in.V0 / rho);
  out.push_back(at_bar / (ad::DensityDt(s.S) * ad::DensityDt(s.S)));
  return out;
}

KernelCheck DensityCheck(const SceneState& s) {
  const std::size_t n = s.S.n;
  KernelCheck k{1e-5, {}, Ones(3 * n, 0.1), {}, {}};
  Put(s.x, &k.at);
  // A nonzero λ, as in a second pass.
  Vector lambda(n, 0.0);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 0.05);
  for (std::int32_t i : s.S.movers) lambda[std::size_t(i)] = g(rng);
  k.at.insert(k.at.end(), lambda.begin(), lambda.end());
  k.at.push_back(s.theta[ad::kRestDensity]);
  k.at.push_back(s.theta[ad::kAlphaDensity]);
  for (double v : Ones(n, 0.05)) k.scale.push_back(v);
  k.scale.push_back(s.theta[ad::kRestDensity] * 0.1);
  k.scale.push_back(s.theta[ad::kAlphaDensity]);
  k.f = [&s](const Vector& z) { return DensityOutputs(s, z); };
  k.vjp = [&s](const Vector& z, const Vector& u) { return DensityVjp(s, z, u); };
  return k;
}

// The bond kernels' parameters: the two stiffnesses and the muscle strength.
constexpr int kBondParameters[3] = {ad::kBondStiffnessBody, ad::kBondStiffnessOther,
                                    ad::kMuscleStrength};

// A bond pass's inputs, unpacked from the checked vector: positions, multipliers, and the
// scene's parameters with kBondParameters from it.
struct BondInputs {
  Field<double> p;
  Vector l;
  Parameters<double> t;
};

BondInputs UnpackBond(const SceneState& s, const Vector& z) {
  BondInputs in;
  std::size_t i = 0;
  in.p = TakeField(z, &i, s.S.n);
  in.l = Take(z, &i, s.S.bonds.size());
  in.t = s.theta;
  for (int id : kBondParameters) in.t[id] = z[i++];
  return in;
}

Vector BondOutputs(const SceneState& s, bool jacobi, const Vector& z) {
  BondInputs in = UnpackBond(s, z);
  if (jacobi)
    ad::BondPassJacobi(s.S, in.t, &in.p, &in.l);
  else
    ad::BondPass(s.S, in.t, &in.p, &in.l);
  Vector out;
  Put(in.p, &out);
  out.insert(out.end(), in.l.begin(), in.l.end());
  return out;
}

// The Jacobi pass's backward needs the forward's per-bond particle and partner positions: the
// forward is rerun on copies to record them.
Vector BondVjp(const SceneState& s, bool jacobi, const Vector& z, const Vector& u) {
  const std::size_t n = s.S.n, nb = s.S.bonds.size();
  const BondInputs in = UnpackBond(s, z);
  Parameters<double> tb{};
  std::size_t i = 0;
  Field<double> pb = TakeField(u, &i, n);
  Vector lb = Take(u, &i, nb);
  if (jacobi) {
    std::vector<Vec3d> particles(nb), partners(nb);
    Field<double> q = in.p;
    Vector lq = in.l;
    ad::BondPassJacobi(s.S, in.t, &q, &lq, &partners, &particles);
    ad::BondPassJacobiBackward(s.S, in.t, in.l, particles, partners, &pb, &lb, &tb);
  } else {
    ad::BondPassBackward(s.S, in.t, in.p, in.l, &pb, &lb, &tb);
  }
  Vector out;
  Put(pb, &out);
  out.insert(out.end(), lb.begin(), lb.end());
  for (int id : kBondParameters) out.push_back(tb[id]);
  return out;
}

// A bond pass (the unsplit step's Gauss-Seidel one, or with `jacobi` the split step's):
// positions, multipliers and the stiffness parameters in.
KernelCheck BondCheck(const SceneState& s, bool jacobi) {
  const std::size_t n = s.S.n, nb = s.S.bonds.size();
  KernelCheck k{1e-5, {}, Ones(3 * n, 0.1), {}, {}};
  Put(s.x, &k.at);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1e-3);
  for (std::size_t b = 0; b < nb; ++b) k.at.push_back(g(rng));
  for (int id : kBondParameters) k.at.push_back(s.theta[id]);
  for (double v : Ones(nb, 1e-3)) k.scale.push_back(v);
  for (int id : kBondParameters) k.scale.push_back(s.theta[id]);
  k.f = [&s, jacobi](const Vector& z) { return BondOutputs(s, jacobi, z); };
  k.vjp = [&s, jacobi](const Vector& z, const Vector& u) { return BondVjp(s, jacobi, z, u); };
  return k;
}

KernelCheck BoxCheck(const SceneState& s) {
  const std::size_t n = s.S.n;
  KernelCheck k{1e-5, {}, Ones(3 * n + 1, 0.1), {}, {}};
  Put(s.x, &k.at);
  k.at.push_back(s.theta[ad::kFloorHeight]);
  k.f = [&s, n](const Vector& z) {
    std::size_t i = 0;
    Field<double> p = TakeField(z, &i, n);
    ad::BoxPass(s.S, z[i], &p);
    Vector out;
    Put(p, &out);
    return out;
  };
  k.vjp = [&s, n](const Vector& z, const Vector& u) {
    std::size_t i = 0, j = 0;
    const Field<double> p = TakeField(z, &i, n);
    Field<double> pb = TakeField(u, &j, n);
    double floor_bar = 0;
    ad::BoxPassBackward(s.S, z[i], p, &pb, &floor_bar);
    Vector out;
    Put(pb, &out);
    out.push_back(floor_bar);
    return out;
  };
  return k;
}

// A projection's output for the velocity kernels: the scene's positions with the moving
// particles displaced by N(0, 0.05 cu) per axis.
Field<double> ProjectedPositions(const SceneState& s, std::uint64_t seed) {
  Field<double> p = s.x;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 0.05);
  for (std::int32_t i : s.S.movers)
    for (double& c : p[std::size_t(i)]) c += g(rng);
  return p;
}

// The split step's velocity correction: x, p, the input velocity and the restitution in (the
// floor as the scene's, with particles below it: the restitution applies to some).
KernelCheck VelocityCorrectionCheck(const SceneState& s) {
  const std::size_t n = s.S.n;
  KernelCheck k{1e-4, {}, Ones(9 * n, 1e-2), {}, {}};
  const Field<double> p = ProjectedPositions(s, 17);
  Put(s.x, &k.at);
  Put(p, &k.at);
  Put(s.v, &k.at);
  k.at.push_back(s.theta[ad::kRestitution]);
  k.scale.push_back(0.1);
  const double floor = s.theta[ad::kFloorHeight], H = s.S.dt * 7;
  k.f = [&s, n, floor, H](const Vector& z) {
    std::size_t i = 0;
    const Field<double> x = TakeField(z, &i, n), p = TakeField(z, &i, n);
    Field<double> v = TakeField(z, &i, n), xn = x;
    ad::CorrectVelocity(s.S, H, floor, z[i], x, p, &v, &xn);
    Vector out;
    Put(v, &out);
    Put(xn, &out);
    return out;
  };
  k.vjp = [&s, n, floor, H](const Vector& z, const Vector& u) {
    std::size_t i = 0, j = 0;
    const Field<double> x = TakeField(z, &i, n), p = TakeField(z, &i, n);
    const Field<double> v = TakeField(z, &i, n);
    const Field<double> vb = TakeField(u, &j, n), xnb = TakeField(u, &j, n);
    Field<double> xb(n, Vec3d{0, 0, 0}), pb = xb, vin_b = xb;
    for (std::size_t q = 0; q < n; ++q)  // a fixed particle: x' = x, v' = v
      if (!s.S.moving[q]) xb[q] = xnb[q], vin_b[q] = vb[q];
    double eb = 0;
    ad::CorrectVelocityBackward(s.S, H, floor, z[i], x, p, v, vb, xnb, &xb, &vin_b, &pb, &eb);
    Vector out;
    Put(xb, &out);
    Put(pb, &out);
    Put(vin_b, &out);
    out.push_back(eb);
    return out;
  };
  return k;
}

KernelCheck VelocityCheck(const SceneState& s) {
  const std::size_t n = s.S.n;
  KernelCheck k{1e-4, {}, Ones(6 * n, 1e-2), {}, {}};
  const Field<double> p = ProjectedPositions(s, 13);
  Put(s.x, &k.at);
  Put(p, &k.at);
  k.at.push_back(s.theta[ad::kRestitution]);
  k.scale.push_back(0.1);
  const double floor = s.theta[ad::kFloorHeight];
  k.f = [&s, n, floor](const Vector& z) {
    std::size_t i = 0;
    const Field<double> x = TakeField(z, &i, n), p = TakeField(z, &i, n);
    Field<double> v, xn;
    ad::UpdateVelocity(s.S, floor, z[i], x, p, &v, &xn);
    Vector out;
    Put(v, &out);
    Put(xn, &out);
    return out;
  };
  k.vjp = [&s, n, floor](const Vector& z, const Vector& u) {
    std::size_t i = 0, j = 0;
    const Field<double> x = TakeField(z, &i, n), p = TakeField(z, &i, n);
    const Field<double> vb = TakeField(u, &j, n), xnb = TakeField(u, &j, n);
    Field<double> xb(n, Vec3d{0, 0, 0}), pb = xb;
    double eb = 0;
    ad::UpdateVelocityBackward(s.S, floor, z[i], x, p, vb, xnb, &xb, &pb, &eb);
    Vector out;
    Put(xb, &out);
    Put(pb, &out);
    out.push_back(eb);
    return out;
  };
  return k;
}

// The whole step's inputs, unpacked from the checked vector: positions, velocities, parameters.
struct StepInputs {
  Field<double> x, v;
  Parameters<double> t;
};

StepInputs UnpackStep(std::size_t n, const Vector& z) {
  StepInputs in;
  std::size_t i = 0;
  in.x = TakeField(z, &i, n);
  in.v = TakeField(z, &i, n);
  in.t = TakeParameters(z, &i);
  return in;
}

Vector StepOutputs(const SceneState& s, const Vector& z) {
  const StepInputs in = UnpackStep(s.S.n, z);
  Field<double> xn, vn;
  ad::StepForward(s.S, in.t, in.x, in.v, &xn, &vn, nullptr);
  Vector out;
  Put(xn, &out);
  Put(vn, &out);
  return out;
}

// The step's VJP from its tape: the forward rerun with one.
Vector StepVjp(const SceneState& s, const Vector& z, const Vector& u) {
  const std::size_t n = s.S.n;
  const StepInputs in = UnpackStep(n, z);
  Field<double> xn, vn;
  Parameters<double> tb{};
  ad::StepTape tape;
  ad::StepForward(s.S, in.t, in.x, in.v, &xn, &vn, &tape);
  std::size_t i = 0;
  Field<double> xb = TakeField(u, &i, n), vb = TakeField(u, &i, n);
  ad::StepBackward(s.S, in.t, tape, &xb, &vb, &tb);
  Vector out;
  Put(xb, &out);
  Put(vb, &out);
  out.insert(out.end(), tb.begin(), tb.end());
  return out;
}

KernelCheck StepCheck(const SceneState& s) {
  const std::size_t n = s.S.n;
  // Positions by 0.1 cu: along 1 cu directions (two-thirds of the spacing) the K composed
  // projections' second-order term leaves ε = 1e-3's central difference 1e-4 to 5e-3 away
  // (ε = 1e-5 agrees to 1e-8), a truncation error, not the VJP's.
  KernelCheck k{1e-5, {}, Ones(3 * n, 0.1), {}, {}};
  Put(s.x, &k.at);
  Put(s.v, &k.at);
  // The floor below the liquid here: the box kernel's own check covers clamping, and a block
  // starting below the floor would be flung up by a jump no difference quotient follows.
  Parameters<double> theta = s.theta;
  theta[ad::kFloorHeight] = -5.0;
  k.at.insert(k.at.end(), theta.begin(), theta.end());
  for (double v : Ones(3 * n, 0.05)) k.scale.push_back(v);
  for (double v : ParameterScale(theta)) k.scale.push_back(v);
  // Muscle activation makes the parameter reach the bonds; fixed particles' x and v are inputs
  // the step never moves (their cotangents are zero in both).
  k.f = [&s](const Vector& z) { return StepOutputs(s, z); };
  k.vjp = [&s](const Vector& z, const Vector& u) { return StepVjp(s, z, u); };
  return k;
}

double Dot(const Vector& a, const Vector& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

void RunKernel(const std::string& name, const KernelCheck& k, const GradCheckOptions& o,
               std::mt19937_64* rng, GradCheckSummary* out) {
  std::normal_distribution<double> g(0, 1);
  const std::size_t outputs = k.f(k.at).size();
  for (double eps : {1e-3, k.epsilon})
    for (std::size_t d = 0; d < o.directions; ++d) {
      Vector dir(k.at.size()), u(outputs), plus = k.at, minus = k.at;
      for (std::size_t i = 0; i < dir.size(); ++i) dir[i] = g(*rng) * k.scale[i];
      for (double& c : u) c = g(*rng);
      for (std::size_t i = 0; i < dir.size(); ++i) {
        plus[i] += eps * dir[i];
        minus[i] -= eps * dir[i];
      }
      GradCheckTest t;
      t.kernel = name;
      t.epsilon = eps;
      t.direction = d;
      t.tolerance = o.tolerance;
      t.finite_difference = (Dot(u, k.f(plus)) - Dot(u, k.f(minus))) / (2 * eps);
      Vector back = k.vjp(k.at, u);
      if (o.sabotage == name) back[back.size() / 2] = -back[back.size() / 2];
      t.analytic = Dot(back, dir);
      t.relative_error = RelativeError(t.finite_difference, t.analytic);
      t.pass = std::isfinite(t.relative_error) && t.relative_error <= t.tolerance;
      std::ostringstream s;
      s << name << " eps=" << eps << " direction " << d;
      t.name = s.str();
      out->tests.push_back(t);
    }
}

}  // namespace

const std::vector<std::string>& GradCheckKernels() {
  static const std::vector<std::string> names = {"sph_density",
                                                 "forces",
                                                 "predict",
                                                 "density_projection",
                                                 "bond_projection",
                                                 "bond_projection_jacobi",
                                                 "box",
                                                 "velocity",
                                                 "velocity_correction",
                                                 "step",
                                                 "reverse"};
  return names;
}

void RunEndToEnd(const GradCheckOptions& o, std::mt19937_64* rng, GradCheckSummary* out);

GradCheckSummary RunGradCheck(const GradCheckOptions& options) {
  std::vector<std::string> kernels = options.kernels;
  if (kernels.empty() || (kernels.size() == 1 && kernels[0] == "all")) kernels = GradCheckKernels();
  for (const std::string& k : kernels)
    if (std::find(GradCheckKernels().begin(), GradCheckKernels().end(), k) ==
        GradCheckKernels().end()) {
      std::string known;
      for (const std::string& n : GradCheckKernels()) known += (known.empty() ? "" : ", ") + n;
      throw InputError("gradcheck: unknown kernel '" + k + "': expected all or one of " + known);
    }
  const SceneState scene = MakeScene(options.seed);
  std::mt19937_64 rng(options.seed);
  GradCheckSummary out;
  for (const std::string& name : kernels) {
    if (name == "reverse") {
      RunEndToEnd(options, &rng, &out);
      continue;
    }
    const KernelCheck k = name == "sph_density"              ? SphDensityCheck(scene)
                          : name == "forces"                 ? ForcesCheck(scene)
                          : name == "predict"                ? PredictCheck(scene)
                          : name == "density_projection"     ? DensityCheck(scene)
                          : name == "bond_projection"        ? BondCheck(scene, false)
                          : name == "bond_projection_jacobi" ? BondCheck(scene, true)
                          : name == "velocity_correction"    ? VelocityCorrectionCheck(scene)
                          : name == "box"                    ? BoxCheck(scene)
                          : name == "velocity"               ? VelocityCheck(scene)
                                                             : StepCheck(scene);
    RunKernel(name, k, options, &rng, &out);
  }
  out.pass = !out.tests.empty();
  for (const GradCheckTest& t : out.tests) out.pass = out.pass && t.pass;
  return out;
}

std::string GradCheckSummary::BriefReport() const {
  std::size_t passed = 0;
  double worst = 0;
  for (const GradCheckTest& t : tests) {
    passed += t.pass;
    worst = std::max(worst, t.relative_error);
  }
  std::ostringstream s;
  s << passed << "/" << tests.size() << " finite-difference tests pass, worst relative error "
    << worst << (pass ? "" : " (FAIL)");
  return s.str();
}

}  // namespace owval::engine

namespace owval::engine {

// The default end-to-end loss: the elastic and liquid centroids at every 20th of `steps` steps
// against the model's own trajectory at shifted parameters (ρ_rest +1%, bond stiffness −10%,
// viscosity ×1.5).
std::vector<LossTerm> SelfReferencedLoss(const SiberneticConfig& config,
                                         const DifferentiableXpbd& model,
                                         const std::vector<double>& theta, std::size_t steps) {
  std::vector<double> shifted = theta;
  shifted[ad::kRestDensity] *= 1.01;
  shifted[ad::kBondStiffnessBody] *= 0.9;
  shifted[ad::kBondStiffnessOther] *= 0.9;
  shifted[ad::kViscosity] *= 1.5;
  const auto reference = model.Trajectory(shifted, steps);
  std::vector<LossTerm> loss(2);
  for (std::size_t i = 0; i < config.particle_count(); ++i) {
    const float type = config.position[i][3];
    if (int(type) == 2) loss[0].particles.push_back(std::int32_t(i));
    if (int(type) == 1) loss[1].particles.push_back(std::int32_t(i));
  }
  if (loss[1].particles.empty()) loss.pop_back();
  if (loss[0].particles.empty()) loss.erase(loss.begin());
  for (LossTerm& term : loss) {
    term.target = LossTerm::Target::kCentroid;
    for (std::size_t t = 20; t <= steps; t += 20) {
      term.frame_steps.push_back(t);
      Vec3d c{0, 0, 0};
      for (std::int32_t i : term.particles)
        for (int a = 0; a < 3; ++a) c[a] += reference[t - 1][std::size_t(i)][a];
      for (double& v : c) v /= double(term.particles.size());
      term.reference.push_back({c});
    }
  }
  return loss;
}

namespace {

// The end-to-end test's problem: the configuration's model at its default parameters (with the
// options' α_density and density passes), its loss, and the checkpointed reverse pass's gradient
// at the model's initial state.
struct EndToEndProblem {
  SiberneticConfig config;
  PhysicsConstants constants;
  std::vector<double> theta;
  std::vector<LossTerm> loss;
  GradientSummary gradient;
  std::vector<Vec3d> x0, v0;
  std::vector<std::int32_t> movers;
};

EndToEndProblem EndToEndProblemOf(const GradCheckOptions& o) {
  if (o.end_to_end_config.empty())
    throw InputError("gradcheck reverse: no configuration for the end-to-end test");
  EndToEndProblem p;
  p.config = ReadSiberneticConfig(o.end_to_end_config);
  if (o.end_to_end_density_passes >= 0)
    p.constants.xpbd.density_passes = o.end_to_end_density_passes;
  DifferentiableXpbd model(p.config, p.constants);
  p.theta = model.DefaultParameters();
  if (o.end_to_end_alpha_density >= 0) p.theta[ad::kAlphaDensity] = o.end_to_end_alpha_density;
  const std::size_t N = o.end_to_end_steps;
  p.loss = o.end_to_end_loss.empty() ? SelfReferencedLoss(p.config, model, p.theta, N)
                                     : o.end_to_end_loss;
  GradientOptions go;
  go.steps = N;
  go.checkpoint_every = 10;
  p.gradient = model.Gradient(p.theta, p.loss, go);
  p.x0 = model.initial_positions(), p.v0 = model.initial_velocities();
  p.movers = model.moving();
  return p;
}

// A random direction in (x0, v0, θ): moving particles' positions by N(0, 1e-2) cu and velocities
// by N(0, 1e-3) per axis, each parameter by N(0, 1%) of its magnitude (1e-2 when it is zero, and
// for the restitution). `gauss` is the test's one distribution: it keeps a draw between calls.
struct Direction {
  std::vector<Vec3d> dx, dv;
  std::vector<double> dtheta;
};

Direction RandomDirection(const EndToEndProblem& p, std::normal_distribution<double>* gauss,
                          std::mt19937_64* rng) {
  Direction d;
  d.dx.assign(p.x0.size(), Vec3d{0, 0, 0});
  d.dv = d.dx;
  for (std::int32_t i : p.movers)
    for (int a = 0; a < 3; ++a) {
      d.dx[std::size_t(i)][a] = (*gauss)(*rng) * 1e-2;
      d.dv[std::size_t(i)][a] = (*gauss)(*rng) * 1e-3;
    }
  d.dtheta.resize(p.theta.size());
  for (std::size_t q = 0; q < p.theta.size(); ++q)
    d.dtheta[q] = (*gauss)(*rng) * (p.theta[q] != 0 ? std::abs(p.theta[q]) * 1e-2 : 1e-2);
  d.dtheta[ad::kRestitution] = (*gauss)(*rng) * 1e-2;
  return d;
}

// The loss over `steps` steps from the problem's (x0, v0, θ) moved by sign·ε along d, by a fresh
// model.
double LossAlong(const EndToEndProblem& p, const Direction& d, double eps, double sign,
                 std::size_t steps) {
  std::vector<Vec3d> x = p.x0, v = p.v0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      x[i][a] += sign * eps * d.dx[i][a];
      v[i][a] += sign * eps * d.dv[i][a];
    }
  std::vector<double> t = p.theta;
  for (std::size_t q = 0; q < t.size(); ++q) t[q] += sign * eps * d.dtheta[q];
  DifferentiableXpbd m = DifferentiableXpbd(p.config, p.constants);
  m.SetInitialState(x, v);
  return m.Loss(t, p.loss, steps);
}

// The reverse pass's derivative along d: its gradient dotted with d, particle by particle, then
// the parameters.
double AnalyticAlong(const GradientSummary& g, const Direction& d) {
  double an = 0;
  for (std::size_t i = 0; i < d.dx.size(); ++i)
    for (int a = 0; a < 3; ++a)
      an += g.position_gradient[i][a] * d.dx[i][a] + g.velocity_gradient[i][a] * d.dv[i][a];
  for (std::size_t q = 0; q < d.dtheta.size(); ++q) an += g.parameter_gradient[q] * d.dtheta[q];
  return an;
}

std::string EndToEndTestName(const GradCheckOptions& o, const EndToEndProblem& p, double eps,
                             std::size_t direction) {
  std::ostringstream s;
  s << "reverse " << o.end_to_end_steps << " steps (" << o.end_to_end_config << ", "
    << (o.end_to_end_loss.empty() ? "centroids vs shifted parameters" : o.end_to_end_loss_name)
    << ", alpha_density=" << p.theta[ad::kAlphaDensity]
    << ", density_passes=" << p.constants.xpbd.density_passes << ") eps=" << eps << " direction "
    << direction;
  return s.str();
}

}  // namespace

// The end-to-end test: at α_density = end_to_end_alpha_density, the end-to-end loss over
// end_to_end_steps steps, differentiated by the checkpointed reverse pass along random
// directions in (x0, v0, θ).
void RunEndToEnd(const GradCheckOptions& o, std::mt19937_64* rng, GradCheckSummary* out) {
  const EndToEndProblem p = EndToEndProblemOf(o);
  const std::size_t N = o.end_to_end_steps;
  std::normal_distribution<double> gauss(0, 1);
  // DD001's ε and this test's own, 3e-3 (not the kernels' 1e-5): the 100-step forward pass
  // amplifies double rounding to a relative noise of ~1e-9 in demo1's loss, so the quotient's
  // noise error (σ/ε) and truncation error (ε²·|L‴|/6) balance near ε = 1e-3. Measured over 10
  // directions (seed 2): worst relative error 4.5e-5 at 1e-3, 1.8e-4 at 3e-3, 7.0e-4 at 3e-4,
  // and at 1e-4 and 1e-5 up to 1.7e-3 and 2.5e-3: the noise, not the derivative.
  for (double eps : {1e-3, 3e-3})
    for (std::size_t d = 0; d < o.directions; ++d) {
      const Direction dir = RandomDirection(p, &gauss, rng);
      GradCheckTest t;
      t.kernel = "reverse";
      t.epsilon = eps;
      t.direction = d;
      t.tolerance = o.end_to_end_tolerance;
      t.finite_difference =
          (LossAlong(p, dir, eps, 1, N) - LossAlong(p, dir, eps, -1, N)) / (2 * eps);
      double an = AnalyticAlong(p.gradient, dir);
      if (o.sabotage == "reverse") an = -an;
      t.analytic = an;
      t.relative_error = RelativeError(t.finite_difference, an);
      t.pass = std::isfinite(t.relative_error) && t.relative_error <= t.tolerance;
      t.name = EndToEndTestName(o, p, eps, d);
      out->tests.push_back(t);
    }
}

}  // namespace owval::engine
