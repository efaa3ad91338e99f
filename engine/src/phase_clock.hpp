#pragma once
// Wall time per named phase of a step, behind Solver::EnablePhaseTiming and phase_seconds(): a
// scheme names its phases once, calls Start() as a step begins and Mark(p) as phase p ends.
// Switched off (the default), Start and Mark are one branch each, so runs pay nothing for it.
#include <array>
#include <chrono>
#include <cstddef>
#include <vector>

#include "owval/engine/solver.hpp"

namespace owval::engine::internal {

template <std::size_t kPhases>
class PhaseClock {
 public:
  explicit PhaseClock(const std::array<const char*, kPhases>& names) : names_(names) {}

  void Enable() { enabled_ = true; }
  // The step begins: time spent between steps belongs to no phase.
  void Start() {
    if (enabled_) mark_ = Clock::now();
  }
  // Phase p ends: the time since the last Start or Mark is added to it.
  void Mark(std::size_t p) {
    if (!enabled_) return;
    const Clock::time_point now = Clock::now();
    seconds_[p] += std::chrono::duration<double>(now - mark_).count();
    mark_ = now;
  }
  std::vector<Solver::PhaseTime> seconds() const {
    std::vector<Solver::PhaseTime> out;
    for (std::size_t p = 0; p < kPhases; ++p) out.push_back({names_[p], seconds_[p]});
    return out;
  }

 private:
  using Clock = std::chrono::steady_clock;
  std::array<const char*, kPhases> names_;
  std::array<double, kPhases> seconds_{};
  bool enabled_ = false;
  Clock::time_point mark_;
};

}  // namespace owval::engine::internal
