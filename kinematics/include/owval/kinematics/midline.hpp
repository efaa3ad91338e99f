#pragma once
// The worm's midline as Sibernetic computes it for its worm_motion_log.txt
// (openworm/sibernetic src/owPhysicsFluidSimulator.cpp, update_worm_motion_log_file; read for
// facts, not copied). Elastic particles whose type code t lies in (2.05, 2.25) are grouped by
// their sub-type: bin = int((t + 3e-7 - 2.1) * 1e4) + 1 for t < 2.15, int((t + 3e-7 - 2.2) * 1e4)
// + 1 otherwise; each bin's mean position, in float arithmetic summed in particle order, is
// scaled to millimetres by Sibernetic's float simulationScale. Bins 51..149 are the 99 midline
// points from head to tail; an empty bin is (0, 0, 0).
//
// Body-plane axes: the worm lies on the floor (gravity along -y), so its plane is (z, x).
// worm_motion_log's "X:" block is the mean z, "Y:" the mean x, "Z:" the mean y; WCON's x and y
// (owval) are the simulation's z and x, the same swap.
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "owval/base/atomic_output.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::kinematics {

constexpr int kFirstMidlineBin = 51;  // Sibernetic prints its bins 51..149 only
constexpr int kMidlineBins = 99;      // bins 51..149
// Sibernetic's compile-time float simulationScale (metres per configuration unit) for its
// constant particle mass 2e-12 kg: 0.0037 * mass^(1/3) / 0.00025^(1/3).
constexpr float kSiberneticSimulationScale = 7.39999905e-06f;

// One frame's midline: per bin, mean simulation x, y, z in millimetres (float, as printed).
struct Midline {
  std::array<float, kMidlineBins> x_mm{}, y_mm{}, z_mm{};
  std::array<int, kMidlineBins> count{};  // particles in each bin (0 = empty bin)
};

// Midline bin (1-based, as Sibernetic) of a type code, or 0 when the particle is no midline
// particle.
int MidlineBin(float type_code);
// The printed bin's slot 0..98 of a type code (bin 51 -> 0), or -1 when its bin is not printed.
inline int PrintedBinSlot(float type_code) {
  const int slot = MidlineBin(type_code) - kFirstMidlineBin;
  return slot >= 0 && slot < kMidlineBins ? slot : -1;
}

// The message of the InputError thrown where a worm is needed and IsWorm is false.
inline constexpr const char* kNotAWorm =
    "no worm body: fewer than 10 midline bins (elastic type codes 2.1051..2.1149, 2.2051..2.2149)";

// True when the trajectory's elastic particles carry Sibernetic's midline sub-type codes (at least
// 10 non-empty bins among 51..149): a worm body.
bool IsWorm(const Trajectory& trajectory);

Midline ComputeMidline(const Trajectory& trajectory, std::size_t frame);

// One line of worm_motion_log.txt: "t\tX:\t" 99 values "\tY:\t" ... "\n", %e throughout; t is
// computed as (float)step * (float)dt, as Sibernetic does.
std::string FormatWormMotionLine(const Midline& midline, long step, double time_step_s);

// worm_motion_log.txt for every frame (frame f is step f * log_step), written atomically.
void WriteWormMotionLog(const Trajectory& trajectory, const std::filesystem::path& path);
std::string WormMotionLog(const Trajectory& trajectory);

// worm_motion_log.txt a line per frame as the frames come (the k-th frame appended is step
// k * log_step), renamed into place by Commit(): memory is one line, whatever the run's length.
class WormMotionLogWriter {
 public:
  // `header`: time step and log step.
  WormMotionLogWriter(const std::filesystem::path& path, const Trajectory& header);
  // Frame `frame` of `trajectory` (a whole trajectory's or a streamed one-frame trajectory's).
  void Append(const Trajectory& trajectory, std::size_t frame);
  void Commit() { out_.Commit(); }

 private:
  AtomicOutput out_;
  int log_step_;
  double time_step_s_;
  std::size_t frames_ = 0;
};

}  // namespace owval::kinematics
