// The "worm" view: a camera that frames the worm rather than the box (issue 15).
#include "worm_camera.hpp"

#include <algorithm>
#include <cmath>

#include "owval/render/render.hpp"

namespace owval::render {
namespace {

std::array<double, 3> MovingCentroid(const Trajectory& t, std::size_t frame) {
  std::array<double, 3> c{0, 0, 0};
  std::size_t n = 0;
  for (std::size_t p = 0; p < t.particle_count(); ++p) {
    if (KindOf(t.type[p]) == ParticleKind::kBoundary) continue;
    for (int a = 0; a < 3; ++a) c[a] += t.coordinate(frame, p, a);
    ++n;
  }
  for (double& v : c) v /= std::max<std::size_t>(n, 1);
  return c;
}

}  // namespace

float internal::WormHalfExtent(const Trajectory& t, std::size_t frame, float aspect) {
  const std::array<double, 3> c = MovingCentroid(t, frame);
  double half = 0;
  for (std::size_t p = 0; p < t.particle_count(); ++p) {
    if (KindOf(t.type[p]) == ParticleKind::kBoundary) continue;
    half = std::max({half, std::abs(t.coordinate(frame, p, 2) - c[2]),
                     std::abs(t.coordinate(frame, p, 0) - c[0]) / aspect});
  }
  return static_cast<float>(std::max(half, 1.0));
}

Camera Camera::ForWorm(const Trajectory& t, std::size_t frame, float aspect) {
  // FromBox's top view shows a box of half-diagonal r in a half-height of 1.05 r / cos(fov / 2):
  // a flat box around the centroid, r = the worm's half extent, frames it in ~90% of the height.
  const float half = internal::WormHalfExtent(t, frame, aspect);
  const std::array<double, 3> c = MovingCentroid(t, frame);
  Box box;
  box.xmin = box.xmax = static_cast<float>(c[0]);
  box.ymin = box.ymax = static_cast<float>(c[1]);
  box.zmin = static_cast<float>(c[2]) - half;
  box.zmax = static_cast<float>(c[2]) + half;
  return FromBox(box, "top", aspect);
}

Camera Camera::ForFrame(const Trajectory& t, std::size_t frame, const std::string& view,
                        float aspect) {
  return view == "worm" ? ForWorm(t, frame, aspect) : FromBox(t.box, view, aspect);
}

}  // namespace owval::render
