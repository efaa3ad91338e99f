#pragma once
// A candidate logged more finely than the reference has frames between the paired ones, which
// the other gates do not read (stale_frames reads those beside a pair for copies only): demo1
// logged every 5 steps against the reference's 20, one unpaired frame's moving particles written
// 30 cu aside, passed every gate. No particle can be somewhere for one frame that it could not
// reach in the time between two frames, so each such frame is held to the reference's speeds:
//
//  - PeakSpeed: the fastest a run's particles of one kind travel between two consecutive frames
//    of its own (the chord, |x(t2) - x(t1)| / (t2 - t1), cu/s), over the common window;
//  - Excursions: per particle and interval between two paired frames of the candidate, how far
//    its positions at the frames between stray outside the box its positions at the two pairs
//    span, the largest axis's excess (cu). A path of length L from a to b has every point within
//    L/2 of a or of b, so an honest excursion is at most half the path, and the path at most the
//    fastest speed times the interval.
//
// The unpaired_frames gate divides the worst excursion by the reference's peak speed times the
// interval (GateUnpairedFrames, parity_gates.cpp).
#include <cstddef>
#include <vector>

#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

// One run's peak over its frames, observed in time order.
class PeakSpeed {
 public:
  explicit PeakSpeed(std::vector<std::size_t> members) : members_(std::move(members)) {}

  // The run's frame `frame_index` at `time_s`. An interval that does not advance in time is not
  // measured (the time-base gate judges those); a non-finite distance is the fastest of all.
  void Observe(const FrameRef& frame, std::size_t frame_index, double time_s);

  double speed_cu_s() const { return speed_cu_s_; }
  std::size_t particle() const { return particle_; }
  // The peak interval's frames (the run's own indices).
  std::size_t from_frame() const { return from_frame_; }
  std::size_t to_frame() const { return to_frame_; }
  std::size_t intervals() const { return intervals_; }
  double duration_s() const { return duration_s_; }  // summed over the measured intervals

 private:
  std::vector<std::size_t> members_;
  std::vector<float> last_;  // the members' positions at the last frame, xyz each
  double last_time_s_ = 0;
  std::size_t last_frame_ = 0;
  double speed_cu_s_ = 0;
  std::size_t particle_ = 0, from_frame_ = 0, to_frame_ = 0, intervals_ = 0;
  double duration_s_ = 0;
};

// The candidate's unpaired frames' excursions, in time order: a paired frame, the frames up to
// the next paired frame, that one, and so on. Memory: seven floats a member.
class Excursions {
 public:
  explicit Excursions(std::vector<std::size_t> members) : members_(std::move(members)) {}

  // A frame between the last paired frame and the next (none before the first pair).
  void ObserveUnpaired(const FrameRef& frame);
  // A paired frame, the candidate's `frame_index` at `time_s`: it closes the interval since the
  // last one, whose unpaired frames are then measured against both.
  void ObservePaired(const FrameRef& frame, std::size_t frame_index, double time_s);

  // The worst excursion over its interval's duration (cu/s): what a particle would have to
  // travel at, twice over, to stray that far and be back. Non-finite positions are infinite.
  double speed_cu_s() const { return speed_cu_s_; }
  double excursion_cu() const { return excursion_cu_; }
  std::size_t particle() const { return particle_; }
  std::size_t from_frame() const { return from_frame_; }  // the paired frames around it
  std::size_t to_frame() const { return to_frame_; }
  std::size_t unpaired_frames() const { return unpaired_frames_; }  // measured, in all

 private:
  std::vector<std::size_t> members_;
  std::vector<float> pair_;     // the members' positions at the last paired frame, xyz each
  std::vector<float> lo_, hi_;  // the unpaired frames' bounds since then, xyz each
  double pair_time_s_ = 0;
  std::size_t pair_frame_ = 0;
  std::size_t pending_frames_ = 0;  // unpaired frames seen since the last paired frame
  double speed_cu_s_ = 0, excursion_cu_ = 0;
  std::size_t particle_ = 0, from_frame_ = 0, to_frame_ = 0, unpaired_frames_ = 0;
};

// Per moving kind (PeakSpeed and Excursions, above): the reference's peak speed over its frames in
// the common window, and the excursions of the candidate's frames between its paired ones.
struct SpeedKind {
  SpeedKind(const char* kind_name, const std::vector<std::size_t>& members)
      : name(kind_name), reference(members), candidate(members) {}
  const char* name;
  PeakSpeed reference;
  Excursions candidate;
};

}  // namespace owval::compare::internal
