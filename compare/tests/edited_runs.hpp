#pragma once
// Edited copies of real runs that the gates' tests judge (closest_approach, held_pair,
// liquid_packing, acceleration, stale_frames, unpaired_frames).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <random>

#include "owval/engine/constants.hpp"
#include "owval/engine/run.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::compare::testing_edits {

// owval's PCISPH on demo1's configuration, gravity changed by 1e-6 of its magnitude: the same
// physics, its chaos diverged from Sibernetic's within the first 50 frames.
inline Trajectory HonestDemo1Rerun(double duration_s) {
  engine::RunOptions o;
  o.duration_s = duration_s;
  o.log_step = 20;
  o.threads = 1;
  o.record_fields = false;
  engine::SetConstant(&o.constants, "gravity_y", -9.79999);
  return engine::Run(engine::ReadSiberneticConfig(std::filesystem::path(OWVAL_SHARED_DIR) /
                                                  "reference/demo1/configuration"),
                     o);
}

// One liquid particle at rest at the centre of a 10 cu box, `frames` frames 1 ms apart: a scene in
// which nothing moves beyond a print's rounding.
inline Trajectory ParticleAtRest(int frames) {
  Trajectory t;
  t.box = {0, 10, 0, 10, 0, 10};
  t.type = {1.1f};
  for (int f = 0; f < frames; ++f) {
    const float x[3] = {5, 5, 5};
    t.AppendFrame(f * 1e-3, x);
  }
  return t;
}

// `t` with particle p put `distance_cu` from particle q (along q -> p) at frames [from, to).
inline Trajectory HeldAt(const Trajectory& t, std::size_t p, std::size_t q, double distance_cu,
                         std::size_t from, std::size_t to) {
  Trajectory out = t;
  for (std::size_t f = from; f < to && f < out.frame_count(); ++f) {
    const float* x = out.position(f, p);
    const float* y = out.position(f, q);
    const double d[3] = {double(x[0]) - y[0], double(x[1]) - y[1], double(x[2]) - y[2]};
    const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int a = 0; a < 3; ++a) out.position(f, p)[a] = float(y[a] + distance_cu * d[a] / norm);
  }
  return out;
}

// `t` with every moving (elastic, liquid) particle moved `factor` times as far from the box's
// centre at frames [from, end), the walls left where they are (as a text file edited from frame
// 1 on, which holds the moving particles only): factor > 1 dilates the scene (a liquid 1% wider
// is 3% less dense), < 1 compresses it.
inline Trajectory ScaledAboutTheBoxCentre(const Trajectory& t, double factor, std::size_t from) {
  Trajectory out = t;
  const double centre[3] = {(t.box.xmin + t.box.xmax) / 2, (t.box.ymin + t.box.ymax) / 2,
                            (t.box.zmin + t.box.zmax) / 2};
  for (std::size_t f = from; f < out.frame_count(); ++f)
    for (std::size_t p = 0; p < out.particle_count(); ++p)
      for (int a = 0; a < 3 && KindOf(out.type[p]) != ParticleKind::kBoundary; ++a)
        out.position(f, p)[a] = float(centre[a] + factor * (out.position(f, p)[a] - centre[a]));
  return out;
}

// `t` with independent noise, uniform in [-amplitude_cu, amplitude_cu] on each coordinate of
// every moving particle, at frames [from, end) (seeded: the same copy every time). No simulation
// jitters: a run's positions are integrated from velocities.
inline Trajectory Jittered(const Trajectory& t, double amplitude_cu, std::size_t from,
                           unsigned seed = 1) {
  Trajectory out = t;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-amplitude_cu, amplitude_cu);
  for (std::size_t f = from; f < out.frame_count(); ++f)
    for (std::size_t p = 0; p < out.particle_count(); ++p)
      for (int a = 0; a < 3 && KindOf(out.type[p]) != ParticleKind::kBoundary; ++a)
        out.position(f, p)[a] = float(out.position(f, p)[a] + noise(random));
  return out;
}

// Every `n`th frame of `t`: a reference logged n times less often (its header's time step
// scaled, so that a log step of 1 stays one).
inline Trajectory EveryNthFrame(const Trajectory& t, std::size_t n) {
  Trajectory out = t;
  out.time_s.clear();
  out.positions.clear();
  out.time_step_s = t.time_step_s * double(n);
  for (std::size_t f = 0; f < t.frame_count(); f += n)
    out.AppendFrame(t.time_s[f], t.position(f, 0));
  return out;
}

// `t` with every moving particle's position at frames [from, end) replaced by its mean over the
// `width` frames centred on it (odd width; the window shrinks symmetrically near the ends, so a
// motion at constant velocity is left as it is): a filtered copy, not a simulation.
inline Trajectory MovingAverage(const Trajectory& t, std::size_t width, std::size_t from) {
  Trajectory out = t;
  const std::size_t n = t.frame_count(), half = width / 2;
  for (std::size_t f = from; f < n; ++f) {
    const std::size_t reach = std::min({half, f - from, n - 1 - f});
    for (std::size_t p = 0; p < t.particle_count(); ++p)
      for (int a = 0; a < 3 && KindOf(t.type[p]) != ParticleKind::kBoundary; ++a) {
        double sum = 0;
        for (std::size_t g = f - reach; g <= f + reach; ++g) sum += t.position(g, p)[a];
        out.position(f, p)[a] = float(sum / double(2 * reach + 1));
      }
  }
  return out;
}

// `t` with every particle of `kind` moved `dx_cu` along x at frame `frame` only: one frame
// written displaced, the frames before and after it as they were.
inline Trajectory OneFrameDisplaced(const Trajectory& t, ParticleKind kind, std::size_t frame,
                                    float dx_cu) {
  Trajectory out = t;
  for (std::size_t p = 0; p < t.particle_count(); ++p)
    if (KindOf(t.type[p]) == kind) out.position(frame, p)[0] += dx_cu;
  return out;
}

}  // namespace owval::compare::testing_edits
