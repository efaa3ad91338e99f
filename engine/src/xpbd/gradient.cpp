// Multi-step reverse mode over the differentiable XPBD step (owval/engine/gradient.hpp):
// checkpoints every k steps, each segment recomputed with its tapes when its turn comes.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "owval/base/errors.hpp"
#include "owval/engine/gradient.hpp"
#include "xpbd/differentiable.hpp"

namespace owval::engine {

using internal::adjoint::Field;
using internal::adjoint::Parameters;
using internal::adjoint::StepTape;
namespace ad = internal::adjoint;

const std::vector<std::string>& GradientParameterNames() {
  static const std::vector<std::string> names = {
      "rest_density",  "bond_stiffness_body", "bond_stiffness_other", "viscosity",
      "alpha_density", "floor_height",        "restitution",          "muscle_strength"};
  return names;
}

struct DifferentiableXpbd::Impl {
  ad::Setup<double> setup;
  Parameters<double> defaults;
  std::vector<Vec3d> x0, v0;
};

namespace {

Parameters<double> ToParameters(const std::vector<double>& p) {
  if (p.size() != ad::kParameterCount)
    throw InputError("differentiable xpbd: expected " + std::to_string(ad::kParameterCount) +
                     " parameters, got " + std::to_string(p.size()));
  Parameters<double> t{};
  std::copy(p.begin(), p.end(), t.begin());
  return t;
}

// The loss of the frames compared after step `step`, adding dL/dx to x_bar when given and
// appending its terms r = √(weight·axis weight)·(y − target), Σ r² = the loss, to `residuals`
// when given (one per term, frame and weighted axis; per moving particle for an all-moving term).
double FrameLoss(const ad::Setup<double>& S, const std::vector<LossTerm>& terms, std::size_t step,
                 const Field<double>& x, Field<double>* x_bar,
                 std::vector<double>* residuals = nullptr) {
  double loss = 0;
  for (const LossTerm& term : terms) {
    // frame_steps ascend (CheckLoss).
    const auto at = std::lower_bound(term.frame_steps.begin(), term.frame_steps.end(), step);
    if (at == term.frame_steps.end() || *at != step) continue;
    const std::vector<Vec3d>& ref = term.reference[std::size_t(at - term.frame_steps.begin())];
    auto add = [&](const Vec3d& y, const Vec3d& target, auto&& spread) {
      for (int a = 0; a < 3; ++a) {
        const double r = y[a] - target[a];
        loss += term.weight * term.axis_weight[a] * r * r;
        if (residuals && term.axis_weight[a] != 0)
          residuals->push_back(std::sqrt(term.weight * term.axis_weight[a]) * r);
        if (x_bar) spread(a, 2 * term.weight * term.axis_weight[a] * r);
      }
    };
    if (term.target == LossTerm::Target::kAllMoving) {
      for (std::size_t m = 0; m < S.movers.size(); ++m) {
        const std::int32_t i = S.movers[m];
        add(x[i], ref[m], [&](int a, double g) { (*x_bar)[i][a] += g; });
      }
      continue;
    }
    Vec3d y{0, 0, 0};
    const double w = 1.0 / double(term.particles.size());
    for (std::int32_t i : term.particles)
      for (int a = 0; a < 3; ++a) y[a] += w * x[i][a];
    add(y, ref[0], [&](int a, double g) {
      for (std::int32_t i : term.particles) (*x_bar)[i][a] += w * g;
    });
  }
  return loss;
}

// `steps`: the window the loss is evaluated over; a frame after a step outside 1..steps would
// never be compared, and a loss that silently leaves out a frame is a wrong loss.
void CheckLoss(const ad::Setup<double>& S, const std::vector<LossTerm>& terms, std::size_t steps) {
  for (const LossTerm& t : terms) {
    if (t.reference.size() != t.frame_steps.size())
      throw InputError("loss: " + std::to_string(t.frame_steps.size()) + " frame steps but " +
                       std::to_string(t.reference.size()) + " reference frames");
    const std::size_t want = t.target == LossTerm::Target::kAllMoving ? S.movers.size() : 1;
    for (const auto& f : t.reference)
      if (f.size() != want)
        throw InputError("loss: a reference frame has " + std::to_string(f.size()) +
                         " values, expected " + std::to_string(want));
    for (std::int32_t i : t.particles)
      if (i < 0 || std::size_t(i) >= S.n)
        throw InputError("loss: particle " + std::to_string(i) + " does not exist");
    if (!std::is_sorted(t.frame_steps.begin(), t.frame_steps.end()))
      throw InputError("loss: frame steps must ascend");
    for (std::size_t step : t.frame_steps)
      if (step < 1 || step > steps)
        throw InputError("loss: a frame at step " + std::to_string(step) + ", outside 1.." +
                         std::to_string(steps));
    if (t.target != LossTerm::Target::kAllMoving && t.particles.empty())
      throw InputError("loss: a particle or centroid term names no particle");
  }
}

double Norm2(const Field<double>& f) {
  double s = 0;
  for (const auto& a : f) s += a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
  return s;
}

// The reverse pass: states at every checkpoint kept, each segment's tapes recomputed in turn
// (or every tape kept when k = 0).
class Reverse {
 public:
  Reverse(const ad::Setup<double>& S, const Parameters<double>& theta,
          const std::vector<LossTerm>& terms, const GradientOptions& o, GradientSummary* out)
      : S_(S), theta_(theta), terms_(terms), o_(o), out_(*out) {}

  void Run(const Field<double>& x0, const Field<double>& v0) {
    const auto start = std::chrono::steady_clock::now();
    Forward(x0, v0);
    const auto mid = std::chrono::steady_clock::now();
    Backward();
    out_.forward_seconds = std::chrono::duration<double>(mid - start).count();
    out_.backward_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - mid).count();
  }

 private:
  std::size_t k() const { return o_.checkpoint_every == 0 ? o_.steps : o_.checkpoint_every; }

  void Forward(const Field<double>& x0, const Field<double>& v0) {
    Field<double> x = x0, v = v0, xn, vn;
    for (std::size_t t = 0; t < o_.steps; ++t) {
      if (t % k() == 0) checkpoints_.push_back({x, v});
      StepTape* tape = nullptr;
      if (o_.checkpoint_every == 0) tape = &tapes_.emplace_back();
      live_ = tapes_.size();
      ad::StepForward(S_, theta_, x, v, &xn, &vn, tape);
      ++out_.forward_steps;
      x.swap(xn), v.swap(vn);
      out_.loss += FrameLoss(S_, terms_, t + 1, x, nullptr);
      if (tape) Track(tape->Bytes());
    }
    final_x_ = x;
    Track(0);
  }

  void Track(std::size_t tape_bytes) {
    const std::size_t state = 2 * S_.n * sizeof(Vec3d);
    held_tape_bytes_ += tape_bytes;
    const std::size_t states = checkpoints_.size() + 1;
    out_.stored_states = std::max(out_.stored_states, states + tapes_.size());
    out_.peak_tape_bytes = std::max(out_.peak_tape_bytes, states * state + held_tape_bytes_);
  }

  // Tapes of steps [c, e) from the checkpoint at c (checkpointed mode).
  // The segment's tapes reuse the previous segment's storage (no fresh pages every step).
  void Recompute(std::size_t c, std::size_t e) {
    if (tapes_.size() < e - c) tapes_.resize(e - c);
    live_ = e - c;
    held_tape_bytes_ = 0;
    Field<double> x = checkpoints_[c / k()].x, v = checkpoints_[c / k()].v, xn, vn;
    for (std::size_t t = c; t < e; ++t) {
      StepTape& tape = tapes_[t - c];
      ad::StepForward(S_, theta_, x, v, &xn, &vn, &tape);
      ++out_.forward_steps;
      x.swap(xn), v.swap(vn);
      Track(tape.Bytes());
    }
  }

  void Backward() {
    Field<double> x_bar(S_.n, Vec3d{0, 0, 0}), v_bar = x_bar;
    Parameters<double> theta_bar{};
    const std::size_t N = o_.steps;
    std::size_t segment_start = N;  // tapes_ hold steps [segment_start, ...)
    for (std::size_t t = N; t >= 1; --t) {
      const std::size_t step = t - 1;
      if (o_.checkpoint_every != 0 && step < segment_start) {
        segment_start = step / k() * k();
        Recompute(segment_start, std::min(segment_start + k(), N));
      }
      const std::size_t base = o_.checkpoint_every == 0 ? 0 : segment_start;
      // x_t: the next step's input, the final state, or the next segment's checkpoint.
      const Field<double>& xt = t == N             ? final_x_
                                : t - base < live_ ? tapes_[t - base].x
                                                   : checkpoints_[t / k()].x;
      FrameLoss(S_, terms_, t, xt, &x_bar);
      ad::StepBackward(S_, theta_, tapes_[step - base], &x_bar, &v_bar, &theta_bar);
      Clip(&x_bar, &v_bar);
      if (o_.window > 0 && step > 0 && (N - step) % o_.window == 0) {
        x_bar.assign(S_.n, Vec3d{0, 0, 0});
        v_bar.assign(S_.n, Vec3d{0, 0, 0});
      }
    }
    out_.parameter_gradient.assign(theta_bar.begin(), theta_bar.end());
    out_.position_gradient.assign(x_bar.begin(), x_bar.end());
    out_.velocity_gradient.assign(v_bar.begin(), v_bar.end());
  }

  void Clip(Field<double>* x_bar, Field<double>* v_bar) {
    if (!(o_.clip_norm > 0)) return;
    const double norm = std::sqrt(Norm2(*x_bar) + Norm2(*v_bar));
    if (!(norm > o_.clip_norm)) return;
    const double f = o_.clip_norm / norm;
    for (auto& a : *x_bar)
      for (double& c : a) c *= f;
    for (auto& a : *v_bar)
      for (double& c : a) c *= f;
    ++out_.clipped_steps;
  }

  struct State {
    Field<double> x, v;
  };
  const ad::Setup<double>& S_;
  const Parameters<double>& theta_;
  const std::vector<LossTerm>& terms_;
  const GradientOptions& o_;
  GradientSummary& out_;
  std::vector<State> checkpoints_;
  std::vector<StepTape> tapes_;
  std::size_t live_ = 0;  // tapes_[0, live_) hold the current segment's steps
  std::size_t held_tape_bytes_ = 0;
  Field<double> final_x_;
};

}  // namespace

DifferentiableXpbd::DifferentiableXpbd(const SiberneticConfig& config,
                                       const PhysicsConstants& constants)
    : impl_(std::make_unique<Impl>()) {
  impl_->setup = ad::SetupOf(config, constants);
  impl_->defaults = ad::DefaultParametersOf(config, constants);
  for (std::size_t i = 0; i < config.particle_count(); ++i) {
    const Row4 &x = config.position[i], &v = config.velocity[i];
    impl_->x0.push_back({x[0], x[1], x[2]});
    impl_->v0.push_back(impl_->setup.moving[i] ? Vec3d{v[0], v[1], v[2]} : Vec3d{0, 0, 0});
  }
}
DifferentiableXpbd::~DifferentiableXpbd() = default;
DifferentiableXpbd::DifferentiableXpbd(DifferentiableXpbd&&) noexcept = default;

std::vector<double> DifferentiableXpbd::DefaultParameters() const {
  return {impl_->defaults.begin(), impl_->defaults.end()};
}
std::size_t DifferentiableXpbd::particle_count() const { return impl_->setup.n; }
std::vector<std::int32_t> DifferentiableXpbd::moving() const { return impl_->setup.movers; }
void DifferentiableXpbd::SetMuscleActivation(const std::vector<float>& activation) {
  impl_->setup.activation = activation;
}
void DifferentiableXpbd::SetInitialState(const std::vector<Vec3d>& x, const std::vector<Vec3d>& v) {
  if (x.size() != impl_->setup.n || v.size() != impl_->setup.n)
    throw InputError("differentiable xpbd: initial state of " + std::to_string(x.size()) +
                     " particles, expected " + std::to_string(impl_->setup.n));
  impl_->x0 = x;
  impl_->v0 = v;
}
const std::vector<Vec3d>& DifferentiableXpbd::initial_positions() const { return impl_->x0; }
const std::vector<Vec3d>& DifferentiableXpbd::initial_velocities() const { return impl_->v0; }

std::vector<std::vector<Vec3d>> DifferentiableXpbd::Trajectory(
    const std::vector<double>& parameters, std::size_t steps) const {
  const Parameters<double> theta = ToParameters(parameters);
  Field<double> x(impl_->x0.begin(), impl_->x0.end()), v(impl_->v0.begin(), impl_->v0.end()), xn,
      vn;
  std::vector<std::vector<Vec3d>> frames;
  for (std::size_t t = 0; t < steps; ++t) {
    ad::StepForward(impl_->setup, theta, x, v, &xn, &vn, nullptr);
    x.swap(xn), v.swap(vn);
    frames.emplace_back(x.begin(), x.end());
  }
  return frames;
}

double DifferentiableXpbd::Loss(const std::vector<double>& parameters,
                                const std::vector<LossTerm>& loss, std::size_t steps,
                                std::vector<double>* residuals) const {
  CheckLoss(impl_->setup, loss, steps);
  const Parameters<double> theta = ToParameters(parameters);
  Field<double> x(impl_->x0.begin(), impl_->x0.end()), v(impl_->v0.begin(), impl_->v0.end()), xn,
      vn;
  double total = 0;
  for (std::size_t t = 0; t < steps; ++t) {
    ad::StepForward(impl_->setup, theta, x, v, &xn, &vn, nullptr);
    x.swap(xn), v.swap(vn);
    total += FrameLoss(impl_->setup, loss, t + 1, x, nullptr, residuals);
  }
  return total;
}

GradientSummary DifferentiableXpbd::Gradient(const std::vector<double>& parameters,
                                             const std::vector<LossTerm>& loss,
                                             const GradientOptions& options) const {
  if (options.steps == 0) throw InputError("gradient: steps must be at least 1");
  CheckLoss(impl_->setup, loss, options.steps);
  const Parameters<double> theta = ToParameters(parameters);
  GradientSummary summary;
  Reverse reverse(impl_->setup, theta, loss, options, &summary);
  reverse.Run(Field<double>(impl_->x0.begin(), impl_->x0.end()),
              Field<double>(impl_->v0.begin(), impl_->v0.end()));
  return summary;
}

}  // namespace owval::engine
