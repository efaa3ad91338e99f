#include "group_drift.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace owval::compare::internal {

std::vector<std::size_t> MovingParticles(const Trajectory& t) {
  std::vector<std::size_t> moving;
  for (std::size_t p = 0; p < t.particle_count(); ++p)
    if (KindOf(t.type[p]) != ParticleKind::kBoundary) moving.push_back(p);
  return moving;
}

double MeanParticleDistance(const FrameRef& a, const FrameRef& b,
                            const std::vector<std::size_t>& particles) {
  if (particles.empty()) return 0;
  double sum = 0;
  for (std::size_t p : particles) {
    const float* x = a.trajectory.position(a.frame, p);
    const float* y = b.trajectory.position(b.frame, p);
    sum += std::hypot(double(x[0]) - y[0], double(x[1]) - y[1], double(x[2]) - y[2]);
  }
  return sum / double(particles.size());
}

std::array<double, 3> Extent(const FrameRef& f, const std::vector<std::size_t>& group) {
  std::array<double, 3> out{};
  for (int a = 0; a < 3; ++a) {
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (std::size_t p : group) {
      lo = std::min<double>(lo, f.trajectory.coordinate(f.frame, p, a));
      hi = std::max<double>(hi, f.trajectory.coordinate(f.frame, p, a));
    }
    out[a] = hi - lo;
  }
  return out;
}

// The group's particles' offsets from their centroid (cu), into `out` (its storage reused).
void Offsets(const FrameRef& f, const std::vector<std::size_t>& group,
             const std::array<double, 3>& centroid, std::vector<Eigen::Vector3d>* out) {
  out->resize(group.size());
  for (std::size_t k = 0; k < group.size(); ++k) {
    const float* x = f.trajectory.position(f.frame, group[k]);
    (*out)[k] = {x[0] - centroid[0], x[1] - centroid[1], x[2] - centroid[2]};
  }
}

BodyPose BestFitPose(const std::vector<Eigen::Vector3d>& from,
                     const std::vector<Eigen::Vector3d>& to) {
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t p = 0; p < from.size(); ++p) covariance += from[p] * to[p].transpose();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!covariance.allFinite()) return {kNaN, {kNaN, kNaN, kNaN}};  // a blown-up run has no pose
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  sign(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d rotation = svd.matrixV() * sign * svd.matrixU().transpose();  // to ≈ R from
  BodyPose pose;
  pose.angle_deg =
      std::acos(std::clamp((rotation.trace() - 1) / 2, -1.0, 1.0)) * 180 / std::numbers::pi;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const Eigen::Vector3d& x : to) {
    const Eigen::Vector3d body = rotation.transpose() * x;
    lo = lo.cwiseMin(body), hi = hi.cwiseMax(body);
  }
  for (int a = 0; a < 3; ++a) pose.extent[a] = to.empty() ? 0 : hi[a] - lo[a];
  return pose;
}

}  // namespace owval::compare::internal
