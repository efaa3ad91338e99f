#include "owval/trajectory/tracked_series.hpp"

namespace owval {

TrackedSeriesRecorder::TrackedSeriesRecorder(const Trajectory& header, const Track& track)
    : track_(track) {
  frame_.box = header.box;
  frame_.type = header.type;
  track_.Validate(frame_);
}

void TrackedSeriesRecorder::Add(double time_s, const float* positions) {
  frame_.time_s.clear();
  frame_.positions.clear();
  frame_.AppendFrame(time_s, positions);
  series_.time_s.push_back(time_s);
  series_.value.push_back(track_.ValueAt(frame_, 0));
}

TrackedSeries TrackedSeriesOf(const Trajectory& trajectory, const Track& track) {
  return {trajectory.time_s, track.Series(trajectory)};
}

TrackedSeries ReadTrackedSeries(FrameSource& frames, const Track& track) {
  TrackedSeries series;
  series.value = track.Series(frames);
  series.time_s = frames.header().time_s;
  return series;
}

std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(const TrackedSeries& reference,
                                                                  const TrackedSeries& candidate) {
  return PairFramesByTime(reference.time_s, candidate.time_s);
}

}  // namespace owval
