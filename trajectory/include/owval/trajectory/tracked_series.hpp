#pragma once
// One run's tracked quantity (track.hpp) with its frames' times: all that a fit's targets, an rms
// reference and the pipeline's predictions read of a trajectory, one number a frame however many
// particles it has. Measured frame by frame, from a file (FrameSource) or from frames as an
// engine produces them (TrackedSeriesRecorder), so that what is kept of a run is this series and
// never the run's frames (memory O(particles) + one double a frame).
#include <cstddef>
#include <utility>
#include <vector>

#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval {

struct TrackedSeries {
  std::vector<double> time_s;  // each frame's simulation time
  std::vector<double> value;   // the tracked value at that frame (Track::Series's numbers)
  std::size_t frame_count() const { return time_s.size(); }
};

// Measures the tracked value of frames given one at a time, by Track::ValueAt's arithmetic.
class TrackedSeriesRecorder {
 public:
  // `header`: the trajectory's box and types (its frames are not read). InputError when the
  // track names nothing in it.
  TrackedSeriesRecorder(const Trajectory& header, const Track& track);
  // One frame: every particle's position, 3 floats each, in the header's order.
  void Add(double time_s, const float* positions);
  TrackedSeries Take() { return std::move(series_); }

 private:
  Track track_;
  Trajectory frame_;  // the header's types and the current frame's positions
  TrackedSeries series_;
};

// Of a trajectory in memory (the same numbers as read frame by frame).
TrackedSeries TrackedSeriesOf(const Trajectory& trajectory, const Track& track);
// Read frame by frame. InputError when the track names nothing in the source.
TrackedSeries ReadTrackedSeries(FrameSource& frames, const Track& track);

// PairFramesByTime's pairs (reference, candidate) for two series.
std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(const TrackedSeries& reference,
                                                                  const TrackedSeries& candidate);

}  // namespace owval
