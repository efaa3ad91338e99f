#pragma once
// What a phase follows through a trajectory: one particle's coordinate or a group centroid's, on
// one axis. Every library that tracks a quantity (compare, render, sgd, predict, ci) uses this
// type, and every comparison of two trajectories pairs their frames with PairFramesByTime.
#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval {

enum class Axis : int { kX = 0, kY = 1, kZ = 2 };
const char* AxisName(Axis axis);              // "x", "y", "z"
Axis ParseAxisName(const std::string& name);  // InputError for anything but x, y, z

struct Track {
  std::size_t particle = 0;  // used when `group` is empty
  std::string group;         // "elastic" | "liquid" | "all": the group's centroid
  Axis axis = Axis::kY;

  // "particle 0 y" or "elastic centroid y".
  std::string Describe() const;
  // The tracked value at every frame. InputError when the particle does not exist or the group
  // is unknown or empty in this trajectory.
  std::vector<double> Series(const Trajectory& trajectory) const;
  // The same, read frame by frame (memory O(particles) and one number a frame).
  std::vector<double> Series(FrameSource& frames) const;
  // The tracked value at one frame (same checks as Series).
  double ValueAt(const Trajectory& trajectory, std::size_t frame) const;
  // InputError unless the track names something that exists in the trajectory.
  void Validate(const Trajectory& trajectory) const;

  // {"particle": 0, "axis": "y"} or {"group": "elastic", "axis": "y"}.
  nlohmann::json ToJson() const;
  // Reads that form (missing keys keep their defaults); InputError naming `where` otherwise.
  static Track FromJson(const nlohmann::json& json, const std::string& where);
};

// The one rule that pairs frames of two trajectories: each reference frame with the candidate
// frame at the same simulation time, up to rounding (1% of the finer of the two frame
// intervals). Returns (reference, candidate) frame index pairs in increasing time; frames outside
// the two runs' common time window, or between the other run's frames, have no partner. Frames
// half an interval apart are not paired: one_sprig at k = 3.3e8 (period 4.7% short) written with
// its header's time step changed from 2e-5 to 2.09789e-5 s had its oscillation stretched onto the
// reference's and, compared at the wrong instants, passed every gate.
// `near_misses` (optional): how many reference frames had a candidate frame within half an
// interval but at another time, for reports to say the frame times do not line up.
std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(
    const Trajectory& reference, const Trajectory& candidate, std::size_t* near_misses = nullptr);
// The same rule on the two runs' frame times alone (seconds, increasing).
std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(
    const std::vector<double>& reference_time_s, const std::vector<double>& candidate_time_s,
    std::size_t* near_misses = nullptr);

}  // namespace owval
