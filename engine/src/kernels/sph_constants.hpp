#pragma once
// The numbers the SPH phases use, derived once from PhysicsConstants exactly the way Sibernetic's
// host does (inc/owPhysicsConstant.h, owConfigProperty.cpp:159-253): the base constants are floats,
// products such as h·s and (h·s)² are formed in float, and only the kernel coefficients go
// through double before their final cast. A last-bit difference in any of them is enough to make
// a many-particle run drift away from the reference within a few hundred steps.
#include <cmath>

#include "kernels/fma.hpp"
#include "kernels/kernels.hpp"
#include "owval/engine/config.hpp"

namespace owval::engine::internal {

struct SphConstants {
  float h_cu, h2_cu, r0_cu;
  float cell_size_cu, cell_size_inverse;  // hash cells are 2h wide
  float scale, inverse_scale;             // metres per cu, and its float reciprocal (135135.156)
  float time_step_s;
  float hs_m, hs2_m2, hs6;  // h in metres, h², h⁶ (the density floor's kernel value)
  float scale6;             // s⁶ as (s²·s²)·s², for predicted densities summed in cu
  float mass_kg;
  float mass_wpoly6;          // m·315/(64π hS⁹)
  float mass_grad_wspiky;     // m·(−45/(π hS⁶)), negative
  float mass_lap_wviscosity;  // −m·∇Wspiky
  float surface_tension;  // −1.7e-9 · surfTensCoeff (= m·Wpoly6·s), divided by m after the sum
  float rest_density;
  float elasticity_coefficient, max_muscle_force, non_worm_body_spring_factor;
  float gravity[3];

  static SphConstants From(const PhysicsConstants& c) {
    SphConstants k{};
    k.h_cu = float(c.h_cu);
    k.h2_cu = k.h_cu * k.h_cu;
    k.r0_cu = float(c.r0_cu);
    k.cell_size_cu = 2.0f * k.h_cu;
    k.cell_size_inverse = 1.0f / k.cell_size_cu;
    k.scale = float(c.simulation_scale);
    k.inverse_scale = 1.0f / k.scale;
    k.time_step_s = float(c.time_step_s);
    k.hs_m = k.h_cu * k.scale;
    k.hs2_m2 = k.hs_m * k.hs_m;
    k.hs6 = k.hs2_m2 * k.hs2_m2 * k.hs2_m2;
    const float scale2 = k.scale * k.scale;
    k.scale6 = scale2 * scale2 * scale2;
    k.mass_kg = float(c.mass_kg);
    const double mass = double(k.mass_kg), hs = double(k.hs_m);
    const double wpoly6 = Wpoly6Coefficient(hs);
    const double grad_wspiky = SpikyGradientCoefficient(hs);
    k.mass_wpoly6 = float(mass * wpoly6);
    k.mass_grad_wspiky = float(mass * grad_wspiky);
    k.mass_lap_wviscosity = float(mass * -grad_wspiky);
    const float surf_tens_coeff = k.mass_wpoly6 * k.scale;
    k.surface_tension = float(-c.surface_tension_scale) * surf_tens_coeff;
    k.rest_density = float(c.rest_density);
    k.elasticity_coefficient = float(c.elasticity_coefficient);
    k.max_muscle_force = float(c.max_muscle_force);
    k.non_worm_body_spring_factor = float(c.non_worm_body_spring_factor);
    for (int a = 0; a < 3; ++a) k.gravity[a] = float(c.gravity[a]);
    return k;
  }
};

}  // namespace owval::engine::internal
