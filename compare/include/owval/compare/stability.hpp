#pragma once
// Stability gate (design notes §4): no NaN/Inf, no particle outside the box, no kinetic-energy
// blow-up, density within a range when the trajectory carries density.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::compare {

struct StabilityOptions {
  double box_tolerance_cu = 1.0;  // how far outside the box a particle may be
  // A frame blows up when its mean particle speed exceeds this. 1 m/s is ten times the speed of
  // a particle falling through a 1 mm Sibernetic box, far beyond any physical motion here.
  double speed_limit_m_s = 1.0;
  double simulation_scale = 7.4e-6;  // metres per configuration unit, for finite differences
  double density_min = 0, density_max = 5000;  // kg/m^3, checked only when density is present
  // Fraction of the checked particles a frame may have outside [density_min, density_max]
  // (DualSPHysics's RhopOut rule tolerates a few); 0: none.
  double density_outside_fraction = 0;
  // Check density over liquid particles only (DualSPHysics checks fluid particles; Sibernetic's
  // elastic matter sits near 600 kg/m^3 by construction, its boundary is not a fluid) instead of
  // every particle.
  bool density_liquid_only = false;
};

// DD001's long-run gate (issue 16): NaN, escapes, kinetic blow-up, and density within
// 700-1300 kg/m^3 with at most 1% of the liquid particles outside, per frame.
StabilityOptions LongRunStabilityOptions();

// The gate in words, from the thresholds themselves, for help texts and reports: "NaN, escapes
// (over 1 cu outside the box), kinetic blow-up (mean speed over 1 m/s), density 700-1300 kg/m^3
// with at most 1% of the liquid particles outside".
std::string DescribeStability(const StabilityOptions& options);

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
  std::size_t frames = 0;
  double max_density_outside_fraction = 0;  // worst frame's fraction of checked particles
  bool pass() const;
  nlohmann::json ToJson() const;
  std::string ToTable() const;
  // One line saying why the gate failed (each violated check, its count and first frame), for
  // --quiet runs that print no table; "" when it passed.
  std::string FailureLine() const;
};

StabilityReport CheckStability(const Trajectory& trajectory, const StabilityOptions& options = {});
// The same, frame by frame from a source (its fields read: FrameSource::ReadFields): memory
// O(particles), and the same report as CheckStability of the whole trajectory.
StabilityReport CheckStability(FrameSource& frames, const StabilityOptions& options = {});

// The same checks frame by frame, on a stream (owval run --stability): memory O(particles),
// whatever the number of frames. CheckStability(t) and a monitor fed t's frames agree.
class StabilityMonitor {
 public:
  StabilityMonitor(const Box& box, std::vector<float> type, const StabilityOptions& options = {});
  // One frame: positions (3 a particle, cu); velocities (3 a particle, m/s) and density (kg/m^3)
  // may be null (speed then from the previous frame's positions).
  void Observe(double time_s, const float* positions, const float* velocities,
               const float* density);
  // One frame of a source or trajectory: its velocities and density when it carries them.
  void Observe(const FrameRef& frame);
  const StabilityReport& report() const { return report_; }

 private:
  double MeanSpeed(double time_s, const float* positions, const float* velocities) const;
  Box box_;
  std::vector<float> type_;
  std::vector<std::size_t> moving_, density_checked_;
  StabilityOptions o_;
  StabilityReport report_;
  std::vector<float> previous_;  // positions of the last frame, when speeds come from positions
  double previous_time_s_ = 0;
};

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
// The same frame by frame from a source (its fields read): memory O(particles), the same report.
IncompressibilityReport CheckIncompressibility(FrameSource& frames,
                                               const IncompressibilityOptions& options = {});

// The same frame by frame (issue 16): frames are observed in order, each one's density, and the
// report is CheckIncompressibility's, value for value.
class IncompressibilityMonitor {
 public:
  // header: types (the liquid) of a trajectory of `frames` frames. Throws InputError as
  // CheckIncompressibility when has_density is false.
  IncompressibilityMonitor(const Trajectory& header, std::size_t frames, bool has_density,
                           const IncompressibilityOptions& options = {});
  // Frame `index` (0, 1, ... in order); frame.trajectory must carry density.
  void Observe(std::size_t index, const FrameRef& frame);
  IncompressibilityReport report() const;

 private:
  std::vector<std::size_t> liquid_;
  IncompressibilityOptions o_;
  std::size_t first_ = 0;  // the first frame checked
  IncompressibilityReport report_;
  double sum_ = 0;
  std::size_t count_ = 0;
};

}  // namespace owval::compare
