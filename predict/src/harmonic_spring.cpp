// One elastic particle on one spring to an anchor: a harmonic oscillator along y. Sibernetic's
// spring acceleration is −Δr·k·f (sphFluid.cl: k = elasticityCoefficient in s⁻², no mass; f =
// 0.25 unless both ends are worm body), integrated by semi-implicit Euler (physics sheet §3.5,
// §3.7).
#include <cmath>
#include <cstdio>

#include "owval/base/errors.hpp"
#include "prediction_parts.hpp"

namespace owval::predict::internal {
namespace {
std::string TypeCode(float type) {
  char b[16];
  std::snprintf(b, sizeof b, "%.4g", double(type));
  return b;
}
}  // namespace

Prediction HarmonicSpring(const engine::SiberneticConfig& c, const engine::PhysicsConstants& k,
                          const PredictOptions& o) {
  const engine::Row4 spring = c.connection[0];
  const std::size_t anchor = static_cast<std::size_t>(spring[0]);
  const engine::Row4 e = c.position[0], a = c.position[anchor];
  if (std::abs(e[0] - a[0]) > 1e-3f || std::abs(e[2] - a[2]) > 1e-3f)
    throw InputError(c.source, 0, "harmonic_spring predicts a vertical spring only");
  const double factor = SpringFactor(e[3], a[3], k, o);
  const double k_eff = k.elasticity_coefficient * factor;
  const double omega = std::sqrt(k_eff), dt = k.time_step_s, s = k.simulation_scale;
  const double period = SymplecticEulerPeriod(omega, dt), period_continuous = 2 * kPi / omega;
  const double sag_cu = -k.gravity[1] / k_eff / s;
  const double equilibrium = a[1] - spring[1] - sag_cu;
  const double offset = e[1] - equilibrium;
  const double half_amplitude = std::abs(offset) / std::sqrt(1 - std::pow(omega * dt / 2, 2));
  const std::string factor_source =
      o.omit_quarter_factor ? "omitted on request (--no-quarter-factor)"
      : factor == 1.0       ? "sphFluid.cl: both ends worm body (2.05 < type < 2.25)"
                            : "sphFluid.cl: 0.25 because not both ends are worm body (types " +
                            TypeCode(e[3]) + ", " + TypeCode(a[3]) + ")";
  Prediction p;
  p.predictor = "harmonic_spring";
  p.inputs = {Input("anchor_y", a[1], "cu", ConfigSource(c, Section::kPosition, anchor)),
              Input("start_y", e[1], "cu", ConfigSource(c, Section::kPosition, 0)),
              Input("rest_length", spring[1], "cu", ConfigSource(c, Section::kConnection, 0)),
              Input("spring_factor", factor, "1", factor_source),
              Input("elasticity_coefficient", k.elasticity_coefficient, "s^-2",
                    DefaultSource("4*1.5e-4/mass")),
              Input("time_step", dt, "s", DefaultSource("timeStep")),
              Input("simulation_scale", s, "m/cu", DefaultSource("simulationScale")),
              Input("gravity_y", k.gravity[1], "m/s^2", DefaultSource("gravity_y"))};
  p.predictions = {
      Quantity("zero_crossing_period", period, "s", period, "s",
               "T = 2*pi / ((2/dt) * asin(omega*dt/2)), omega = sqrt(k*f): semi-implicit Euler",
               0.003, kRelative),
      Quantity("period_continuous", period_continuous, "s", period_continuous, "s",
               "T = 2*pi/omega (exact integration; Sibernetic's integrator gives the value above)",
               0, kInformative),
      Quantity("half_amplitude", half_amplitude, "cu", half_amplitude * s, "m",
               "A = |y0 - y_eq| / sqrt(1 - (omega*dt/2)^2) (semi-implicit Euler from rest)", 0.01,
               kRelative),
      Quantity("equilibrium", equilibrium, "cu", equilibrium * s, "m",
               "y_eq = y_anchor - L0 - g/(k*f)/s", 0.01, kAbsoluteCu),
      Quantity("gravity_sag", sag_cu, "cu", sag_cu * s, "m", "g/(k*f)/s", 0, kInformative)};
  p.track = Track{0, "", Axis::kY};
  return p;
}

}  // namespace owval::predict::internal
