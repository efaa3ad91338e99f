// One liquid particle falling from rest: y_n = y0 - g*dt²*n(n+1)/2/s under semi-implicit Euler
// (checked against Sibernetic's test_gravity run). Contact is where the floor's wall particles
// enter the kernel support, within h: from there density, pressure and viscosity act (physics
// sheet §3.3-3.4) and the fall leaves the free-fall curve. Measured: owval's engine and
// Sibernetic's test_gravity follow it within 1e-4 cu until then; the particle slows before it
// reaches r0, where Ihmsen's wall weight starts, so r0 would be the wrong event to time.
#include <algorithm>
#include <cmath>

#include "owval/base/errors.hpp"
#include "prediction_parts.hpp"

namespace owval::predict::internal {

Prediction FreeFall(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k) {
  std::size_t floor_row = 0;
  float floor_y = 1e30f;
  for (std::size_t i = 0; i < c.position.size(); ++i)
    if (KindOf(c.position[i][3]) == ParticleKind::kBoundary && c.position[i][1] < floor_y) {
      floor_y = c.position[i][1];
      floor_row = i;
    }
  if (floor_y == 1e30f) throw InputError(c.source, 0, "free_fall: no wall particles (no floor)");
  const double y0 = c.position[0][1], contact_y = floor_y + k.h_cu, g = -k.gravity[1];
  const double dt = k.time_step_s, s = k.simulation_scale;
  const double drop_m = (y0 - contact_y) * s;
  if (drop_m <= 0 || g <= 0)
    throw InputError(c.source, 0, "free_fall: the particle does not start above the floor");
  const double t_continuous = std::sqrt(2 * drop_m / g);
  // Steps n with g*dt²*n(n+1)/2 = drop (the discrete trajectory), as a real number.
  const double steps = (-1 + std::sqrt(1 + 8 * drop_m / (g * dt * dt))) / 2;
  const double t = steps * dt;
  Prediction p;
  p.predictor = "free_fall";
  p.inputs = {Input("start_y", y0, "cu", ConfigSource(c, Section::kPosition, 0)),
              Input("floor_wall_y", floor_y, "cu",
                    ConfigSource(c, Section::kPosition, floor_row) + ", lowest wall particle"),
              Input("h", k.h_cu, "cu", DefaultSource("h (smoothing radius)")),
              Input("time_step", dt, "s", DefaultSource("timeStep")),
              Input("gravity_y", k.gravity[1], "m/s^2", DefaultSource("gravity_y")),
              Input("simulation_scale", s, "m/cu", DefaultSource("simulationScale"))};
  p.predictions = {
      Quantity("contact_time", t, "s", t, "s",
               "t = n*dt with g*dt^2*n(n+1)/2 = (y0 - y_wall - h)*s (semi-implicit Euler)", 0.005,
               kRelative),
      Quantity("contact_time_continuous", t_continuous, "s", t_continuous, "s",
               "t = sqrt(2*(y0 - y_wall - h)*s/g)", 0, kInformative),
      Quantity("contact_height", contact_y, "cu", contact_y * s, "m",
               "y_wall + h: the wall enters the kernel support", 0, kInformative)};
  p.track = Track{0, "", Axis::kY};
  return p;
}

}  // namespace owval::predict::internal
