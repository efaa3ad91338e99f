#pragma once
// Where the candidate's particles and groups drift from the reference's, pair of frames by pair:
// each group's centroid, extent and pose (DriftAccumulator, the GROUP.* gates) and each kind's
// worst single particle (WorstParticle, GROUP.worst_particle).
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "owval/compare/parity.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

// The reference's moving particles (elastic and liquid), in file order.
std::vector<std::size_t> MovingParticles(const Trajectory& t);

// The mean 3-D distance of `particles` between two frames (cu).
double MeanParticleDistance(const FrameRef& a, const FrameRef& b,
                            const std::vector<std::size_t>& particles);

// The group's bounding-box extent per axis (cu).
std::array<double, 3> Extent(const FrameRef& f, const std::vector<std::size_t>& group);

// The group's particles' offsets from their centroid (cu), into `out` (its storage reused).
void Offsets(const FrameRef& f, const std::vector<std::size_t>& group,
             const std::array<double, 3>& centroid, std::vector<Eigen::Vector3d>* out);

// The rotation R that best maps the offsets `from` onto `to` (least squares, a proper rotation:
// Kabsch, Acta Cryst. A32, 922, 1976), its angle in degrees, and the extents of `to` with R
// undone, per axis of `from`'s frame.
struct BodyPose {
  double angle_deg = 0;
  std::array<double, 3> extent{};
};
BodyPose BestFitPose(const std::vector<Eigen::Vector3d>& from,
                     const std::vector<Eigen::Vector3d>& to);

// One group's drift, accumulated pair by pair in time order.
struct DriftAccumulator {
  std::vector<std::size_t> members;
  GroupDrift d;
  // Offsets at the first paired frame and at the latest one; the pose is fitted once, at the end.
  std::vector<Eigen::Vector3d> first_ref, first_cand, last_ref, last_cand;

  void Observe(const FrameRef& ref, const FrameRef& cand, const Box& box) {
    const auto a = Centroid(ref.trajectory, ref.frame, members),
               b = Centroid(cand.trajectory, cand.frame, members);
    ObservePose(ref, cand, a, b);
    const double dist = std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    d.max_centroid_distance_cu = std::max(d.max_centroid_distance_cu, dist);
    d.final_centroid_distance_cu = dist;
    for (int ax = 0; ax < 3; ++ax) d.final_offset_cu[ax] = b[ax] - a[ax];
    const auto er = Extent(ref, members), ec = Extent(cand, members);
    for (int ax = 0; ax < 3; ++ax) {
      const double extent = box.extent(ax) > 0 ? box.extent(ax) : 1.0;
      d.max_extent_difference_fraction =
          std::max(d.max_extent_difference_fraction, std::abs(ec[ax] - er[ax]) / extent);
      d.final_extent_ratio[ax] = er[ax] > 0 ? ec[ax] / er[ax] : (ec[ax] > 0 ? INFINITY : 1);
    }
  }

  void ObservePose(const FrameRef& ref, const FrameRef& cand, const std::array<double, 3>& a,
                   const std::array<double, 3>& b) {
    if (members.size() < 3) return;  // one or two points have no orientation to speak of
    const bool first = first_ref.empty();
    Offsets(ref, members, a, first ? &first_ref : &last_ref);
    Offsets(cand, members, b, first ? &first_cand : &last_cand);
  }

  // After the last pair: the pose at the last paired frame, when there is one after the first.
  void FinishPose() {
    if (last_ref.empty()) return;
    const BodyPose r = BestFitPose(first_ref, last_ref);
    const BodyPose c = BestFitPose(first_cand, last_cand);
    d.has_pose = true;
    d.final_rotation_deg[0] = r.angle_deg, d.final_rotation_deg[1] = c.angle_deg;
    for (int ax = 0; ax < 3; ++ax)
      d.final_body_extent_ratio[ax] =
          r.extent[ax] > 0 ? c.extent[ax] / r.extent[ax] : (c.extent[ax] > 0 ? INFINITY : 1);
  }
};

// The worst single particle of one kind: max over its particles and the paired frames of
// |x_cand - x_ref| (cu), and where. The particle_distance gates average over every moving
// particle, so one particle sent far away (to a wall, frozen in the air, swapped with another)
// moved demo1's mean by 0.1% of the box and passed; boundary particles were not looked at at all
// (one_sprig's spring anchor moved 10 cu passed).
struct WorstParticle {
  const char* group;
  std::vector<std::size_t> members;
  double distance_cu = 0;
  std::size_t particle = 0, reference_frame = 0;

  void Observe(const FrameRef& ref, const FrameRef& cand, std::size_t reference_frame_index) {
    double worst_squared = distance_cu * distance_cu;
    for (std::size_t p : members) {
      const float* x = ref.trajectory.position(ref.frame, p);
      const float* y = cand.trajectory.position(cand.frame, p);
      const double dx = double(y[0]) - x[0], dy = double(y[1]) - x[1], dz = double(y[2]) - x[2];
      double squared = dx * dx + dy * dy + dz * dz;
      if (!std::isfinite(squared)) squared = INFINITY;  // a NaN is the worst of all
      if (squared > worst_squared) {
        worst_squared = squared;
        distance_cu = std::sqrt(squared);
        particle = p, reference_frame = reference_frame_index;
      }
    }
  }
};

}  // namespace owval::compare::internal
