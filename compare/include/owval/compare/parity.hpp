#pragma once
// Frame-by-frame parity of a candidate trajectory against a reference (design notes §4): the
// report a backend port must pass. Frames are paired by simulation time, so files with different
// log steps or layouts compare correctly.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "owval/compare/signal_metrics.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::compare {

struct ParityOptions {
  // The tracked scalar: a particle's coordinate, or a group centroid's when `group` is set
  // ("elastic", "liquid", "all").
  std::size_t particle = 0;
  std::string group;
  int axis = 1;
  // Reference frame indices to gate; empty means every reference frame that has a partner.
  std::vector<std::size_t> sample_frames;
  // Scale for |cand - ref|; empty means the reference's range over the run.
  std::optional<double> scale;
  double frame_threshold = 0.05;       // pass when |Δ|/scale < this at every sample frame
  double period_gap_threshold = 0.02;  // relative gap of zero-crossing periods
  double amplitude_gap_threshold = 0.05;
};

struct FrameParity {
  std::size_t reference_frame = 0, candidate_frame = 0;
  double time_s = 0;
  double reference_value = 0, candidate_value = 0;
  double relative_difference = 0;  // |cand - ref| / scale
  bool pass = true;
};

struct GroupDrift {
  std::string group;
  double final_centroid_distance_cu = 0;  // |centroid_cand - centroid_ref| at the last paired frame
  double max_centroid_distance_cu = 0;
  double final_extent_ratio[3] = {1, 1, 1};  // bounding-box extent cand/ref per axis, last frame
};

struct ParityReport {
  std::string subject;  // e.g. "particle 0 y"
  double scale = 0;
  std::size_t paired_frames = 0;
  std::vector<FrameParity> frames;  // the gated frames
  std::vector<std::size_t> failing_frames;
  // Mean over particles of |x_cand - x_ref| (cu) at the first paired frame, averaged over all
  // paired frames, and at the last one.
  double l2_initial_cu = 0, l2_mean_cu = 0, l2_final_cu = 0;
  std::vector<GroupDrift> drift;
  SignalMetrics reference_metrics, candidate_metrics;
  std::optional<double> period_gap, half_amplitude_gap, equilibrium_gap_cu;
  bool frames_pass = true, metrics_pass = true;
  bool pass() const { return frames_pass && metrics_pass; }

  nlohmann::json ToJson() const;
  std::string ToMarkdown() const;
  std::string ToTable() const;
};

// Throws InputError when the two trajectories have different particle counts or no frames in
// common time.
ParityReport CompareTrajectories(const Trajectory& reference, const Trajectory& candidate,
                                 const ParityOptions& options);

// Pairs each reference frame with the candidate frame at the same simulation time (within half
// the finer frame interval); returns (reference, candidate) index pairs.
std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(const Trajectory& reference,
                                                                  const Trajectory& candidate);

}  // namespace owval::compare
