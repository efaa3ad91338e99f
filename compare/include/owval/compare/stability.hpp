#pragma once
// Stability gate (design notes §4): no NaN/Inf, no particle outside the box, no kinetic-energy
// blow-up, density within a range when the trajectory carries density.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "owval/trajectory/trajectory.hpp"

namespace owval::compare {

struct StabilityOptions {
  double box_tolerance_cu = 1.0;  // how far outside the box a particle may be
  // A frame blows up when its mean particle speed exceeds this. 1 m/s is ten times the speed of
  // a particle falling through a 1 mm Sibernetic box, far beyond any physical motion here.
  double speed_limit_m_s = 1.0;
  double simulation_scale = 7.4e-6;  // metres per configuration unit, for finite differences
  double density_min = 0, density_max = 5000;  // kg/m^3, checked only when density is present
};

struct ViolationCount {
  std::size_t count = 0;  // particle-frames (or frames for blow-up)
  std::optional<std::size_t> first_frame;
  void Add(std::size_t frame, std::size_t n = 1);
};

struct StabilityReport {
  ViolationCount non_finite, outside_box, blow_up, density_out_of_range;
  bool density_checked = false;
  bool velocities_from_positions = false;
  double max_mean_speed_m_s = 0;
  bool pass() const;
  nlohmann::json ToJson() const;
  std::string ToTable() const;
};

StabilityReport CheckStability(const Trajectory& trajectory, const StabilityOptions& options = {});

struct IncompressibilityOptions {
  double rest_density = 1000;    // rho0, kg/m^3
  double limit = 0.01;           // mean and max |rho/rho0 - 1| must stay below this
  bool skip_first_frame = true;  // frame 0 holds the initial lattice, before any pressure solve
};

struct IncompressibilityReport {
  std::size_t liquid_particles = 0, frames = 0;
  double mean_deviation = 0, max_deviation = 0;
  std::optional<std::size_t> worst_frame, worst_particle;
  double limit = 0.01;
  bool pass() const { return mean_deviation < limit && max_deviation < limit; }
  nlohmann::json ToJson() const;
  std::string ToTable() const;
};

// Throws InputError when the trajectory has no density or no liquid particle.
IncompressibilityReport CheckIncompressibility(const Trajectory& trajectory,
                                               const IncompressibilityOptions& options = {});

}  // namespace owval::compare
