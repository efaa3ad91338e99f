#pragma once
// The numbers one PCISPH step uses, derived once from PhysicsConstants the way Sibernetic's host
// does: in double, then cast to float (owConfigProperty.cpp), so device arithmetic stays float32.
#include <cmath>

#include "owval/engine/config.hpp"

namespace owval::engine::internal {

struct SphConstants {
  float h_cu, h2_cu, r0_cu;
  float scale, inverse_scale;  // metres per cu, and its float reciprocal (135135.156)
  float time_step_s;
  float hs_m, hs2_m2, hs6;  // h in metres, h², h⁶ (the density floor's kernel value)
  float scale6;             // s⁶, for predicted densities summed in cu
  float mass_kg;
  float mass_wpoly6;          // m·315/(64π hS⁹)
  float mass_grad_wspiky;     // m·(−45/(π hS⁶)), negative
  float mass_lap_wviscosity;  // −mass_grad_wspiky
  float surface_tension;  // −1.7e-9 · m·Wpoly6·s / m: acceleration per (hS²−r²)³·Δx[cu]
  float rest_density, delta;
  float elasticity_coefficient, max_muscle_force, non_worm_body_spring_factor;
  float gravity[3];
  int pcisph_iterations;

  static SphConstants From(const PhysicsConstants& c) {
    constexpr double kPi = 3.14159265358979323846;
    SphConstants k{};
    const double hs = c.h_cu * c.simulation_scale;
    k.h_cu = float(c.h_cu);
    k.h2_cu = float(c.h_cu * c.h_cu);
    k.r0_cu = float(c.r0_cu);
    k.scale = float(c.simulation_scale);
    k.inverse_scale = float(1.0 / c.simulation_scale);
    k.time_step_s = float(c.time_step_s);
    k.hs_m = float(hs);
    k.hs2_m2 = float(hs * hs);
    k.hs6 = k.hs2_m2 * k.hs2_m2 * k.hs2_m2;
    k.scale6 = float(std::pow(c.simulation_scale, 6));
    k.mass_kg = float(c.mass_kg);
    const double wpoly6 = 315.0 / (64.0 * kPi * std::pow(hs, 9));
    k.mass_wpoly6 = float(c.mass_kg * wpoly6);
    k.mass_grad_wspiky = float(c.mass_kg * (-45.0 / (kPi * std::pow(hs, 6))));
    k.mass_lap_wviscosity = -k.mass_grad_wspiky;
    // Sibernetic passes surfTensCoeff = m·Wpoly6·s and divides the sum by m (sphFluid.cl:645-655).
    const float surf_tens_coeff = float(c.mass_kg * wpoly6 * c.simulation_scale);
    k.surface_tension = float(-c.surface_tension_scale) * surf_tens_coeff / k.mass_kg;
    k.rest_density = float(c.rest_density);
    k.delta = float(c.delta);
    k.elasticity_coefficient = float(c.elasticity_coefficient);
    k.max_muscle_force = float(c.max_muscle_force);
    k.non_worm_body_spring_factor = float(c.non_worm_body_spring_factor);
    for (int a = 0; a < 3; ++a) k.gravity[a] = float(c.gravity[a]);
    k.pcisph_iterations = c.pcisph_iterations;
    return k;
  }
};

}  // namespace owval::engine::internal
