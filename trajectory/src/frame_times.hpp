#pragma once
// CheckFrameTimesIncrease (trajectory.hpp) for times read one at a time (WconReader's t).
#include <cstddef>
#include <string>

namespace owval {

// InputError naming `file` when frame `frame`'s time is not finite or not after `previous_s`
// (frame `frame` - 1's time, not read when `frame` is 0), worded as CheckFrameTimesIncrease.
void CheckFrameTimeFollows(std::size_t frame, double time_s, double previous_s,
                           const std::string& file, const std::string& where = "");

}  // namespace owval
