#include "phases/pressure_force.hpp"

#include "kernels/kernels.hpp"

namespace owval::engine::internal {

void ComputePressureAcceleration(const SphConstants& k, const ParticleState& s,
                                 const std::vector<float>& density, float short_range_pressure,
                                 std::vector<Float4>* out, int threads) {
  std::vector<Float4>& acceleration = *out;
  const float quarter = k.hs_m / 4;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    const Float4 xi = s.position[i];
    const Neighbour* slots = s.slots(i);
    float sum[3] = {0, 0, 0};
    for (int m = 0; m < kSlots && slots[m].index >= 0; ++m) {
      const float r = slots[m].distance_m;
      if (!(r < k.hs_m)) continue;
      const std::int32_t j = slots[m].index;
      // Below hS/4 a fixed short-range repulsion replaces the pressure term
      // (sphFluid.cl:1000-1010).
      // ∇Wspiky's shape (h − r)²; −(a·a) and (−a)·a are the same float.
      const float t =
          r < quarter ? -SpikyGradientShape(quarter, r) * 0.5f * short_range_pressure / density[j]
                      : -SpikyGradientShape(k.hs_m, r) * 0.5f * (s.pressure[i] + s.pressure[j]) /
                            density[j];
      const Float4 xj = s.position[j];  // direction from x(t), not x* (gotcha 7)
      sum[0] += t * ((xi.x - xj.x) * k.scale) / r;
      sum[1] += t * ((xi.y - xj.y) * k.scale) / r;
      sum[2] += t * ((xi.z - xj.z) * k.scale) / r;
    }
    const float factor = k.mass_grad_wspiky / density[i];
    acceleration[i] = {sum[0] * factor, sum[1] * factor, sum[2] * factor, 0};
  }
}

}  // namespace owval::engine::internal
