#pragma once
// Edited copies of real runs that the pair gates' tests (closest_approach, held_pair) judge.
#include <cmath>
#include <cstddef>

#include "owval/trajectory/trajectory.hpp"

namespace owval::compare::testing_edits {

// `t` with particle p put `distance_cu` from particle q (along q -> p) at frames [from, to).
inline Trajectory HeldAt(const Trajectory& t, std::size_t p, std::size_t q, double distance_cu,
                         std::size_t from, std::size_t to) {
  Trajectory out = t;
  for (std::size_t f = from; f < to && f < out.frame_count(); ++f) {
    const float* x = out.position(f, p);
    const float* y = out.position(f, q);
    const double d[3] = {double(x[0]) - y[0], double(x[1]) - y[1], double(x[2]) - y[2]};
    const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int a = 0; a < 3; ++a) out.position(f, p)[a] = float(y[a] + distance_cu * d[a] / norm);
  }
  return out;
}

}  // namespace owval::compare::testing_edits
