#pragma once
// The constants only PCISPH uses: the pressure scaling δ and the number of prediction-correction
// iterations (Sibernetic: delta fixed from the default time step, 3 iterations; [SP09] §4).
#include "owval/engine/config.hpp"

namespace owval::engine::internal {

struct PcisphConstants {
  float delta;     // Pa per kg/m³ of predicted density error
  int iterations;  // prediction-correction passes per step

  static PcisphConstants From(const PhysicsConstants& c) {
    return {float(c.delta), c.pcisph_iterations};
  }
};

}  // namespace owval::engine::internal
