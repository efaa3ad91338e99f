#pragma once
// The frames of a side-by-side video, drawn one at a time: what RenderSideBySide encodes and what
// CheckSideBySide (video_check.hpp) draws again to compare with a decoded video.
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "owval/render/render.hpp"

namespace owval::render::internal {

// Evenly spaced indices into [0, n), first and last included, at most `cap` of them (0: all).
std::vector<std::size_t> SampleEvenly(std::size_t n, std::size_t cap);

class SideBySideFrames {
 public:
  // Pairs the two runs' frames by time (PairFramesByTime) and samples them down to
  // o.max_frames; InputError when they share no frame time. The sources must outlive this.
  SideBySideFrames(FrameSource& reference, FrameSource& candidate, const RenderOptions& o);
  ~SideBySideFrames();
  SideBySideFrames(const SideBySideFrames&) = delete;
  SideBySideFrames& operator=(const SideBySideFrames&) = delete;

  std::size_t size() const;  // frames in the video
  // Video frame k (RGBA, top row first), valid until the next call; increasing k is the cheap
  // direction through the sources.
  const std::vector<unsigned char>& Draw(std::size_t k);
  // The same frame with every moving particle of the candidate moved `distance_cu` along `axis`
  // (what a video that shows the candidate must show moved).
  const std::vector<unsigned char>& DrawCandidateMoved(std::size_t k, Axis axis, float distance_cu);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace owval::render::internal
