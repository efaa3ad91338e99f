#include "owval/kinematics/body_shape.hpp"

#include <cmath>
#include <vector>

#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"

namespace owval::kinematics {
namespace {

using Vec3 = std::array<double, 3>;

double Distance(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Each midline bin's particle indices (bins 51..149 -> 0..98).
std::vector<std::vector<std::size_t>> Rings(const Trajectory& t) {
  std::vector<std::vector<std::size_t>> rings(kMidlineBins);
  for (std::size_t i = 0; i < t.particle_count(); ++i) {
    if (const int slot = PrintedBinSlot(t.type[i]); slot >= 0)
      rings[std::size_t(slot)].push_back(i);
  }
  return rings;
}

Vec3 Mean(const Trajectory& t, std::size_t frame, const std::vector<std::size_t>& particles) {
  Vec3 sum{};
  for (std::size_t i : particles)
    for (int a = 0; a < 3; ++a) sum[a] += t.position(frame, i)[a];
  for (double& v : sum) v /= double(particles.size());
  return sum;
}

// Twice the mean distance of the ring's particles from its centre.
double RingDiameter(const Trajectory& t, std::size_t frame, const std::vector<std::size_t>& ring,
                    const Vec3& centre) {
  double radius = 0;
  for (std::size_t i : ring) {
    const float* p = t.position(frame, i);
    radius += Distance({p[0], p[1], p[2]}, centre);
  }
  return 2 * radius / double(ring.size());
}

}  // namespace

BodyShape MeasureBodyShape(const Trajectory& t, std::size_t frame) {
  if (!IsWorm(t)) throw InputError(kNotAWorm);
  const auto rings = Rings(t);
  BodyShape shape;
  std::size_t particles = 0;
  std::vector<Vec3> centres;
  double diameter_sum = 0;
  std::size_t diameter_rings = 0;
  for (std::size_t b = 0; b < rings.size(); ++b) {
    if (rings[b].empty()) continue;
    const Vec3 centre = Mean(t, frame, rings[b]);
    for (int a = 0; a < 3; ++a) shape.centre_of_mass_cu[a] += centre[a] * double(rings[b].size());
    particles += rings[b].size();
    centres.push_back(centre);
    if (rings[b].size() < 2) continue;
    shape.ring_diameter_cu[b] = RingDiameter(t, frame, rings[b], centre);
    if (b >= rings.size() / 4 && b < 3 * rings.size() / 4) {
      diameter_sum += shape.ring_diameter_cu[b];
      ++diameter_rings;
    }
  }
  for (double& v : shape.centre_of_mass_cu) v /= double(particles);
  for (std::size_t k = 1; k < centres.size(); ++k)
    shape.span_cu += Distance(centres[k - 1], centres[k]);
  if (diameter_rings) shape.cross_section_diameter_cu = diameter_sum / double(diameter_rings);
  return shape;
}

}  // namespace owval::kinematics
