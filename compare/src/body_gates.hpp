#pragma once
// Scene gates beyond particles and group centroids, for scenes that have the body they measure:
//  - a worm (kinematics::IsWorm on both runs): worm.centre_of_mass (max 3-D distance over the
//    paired frames, of the box; the centroid_distance threshold), worm.span and
//    worm.cross_section_diameter (max relative difference; the body_shape threshold), measured by
//    kinematics::MeasureBodyShape. Ports that let the worm sink or swell fail here
//    (openworm/sibernetic#238); and worm.ring_diameter: max over the paired frames and the rings
//    (midline bins) of a ring's diameter difference, relative to the reference's mid-body
//    cross-section diameter at that frame (a scale that does not vanish where head and tail
//    taper; the body_shape threshold): a part of the body crushed or swollen, its ring means
//    and so its midline and centroid unchanged;
//  - liquid over an elastic sheet (demo2: every elastic particle on one horizontal plane at the
//    first frame, with liquid above it): liquid.fraction_above_membrane, the max difference of
//    the fraction of liquid particles above the sheet's mean height (the
//    membrane_liquid_fraction threshold). A leaking membrane fails here.
//  - an elastic body (two or more elastic particles, some within 1.5 spacings of each other at
//    the reference's first frame): elastic.bond_length, the largest difference of a bond's
//    length over the paired frames, of the body's spacing (ParityGates::bond_length); n/a
//    otherwise. A part of the body out of shape fails here, whatever its motion.
// Scenes without such a body get none of the first two kinds. Measured pair by pair of frames, in
// time order, as PairReducer reads them (pair_reducer.hpp, frame_source.hpp).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "owval/compare/parity.hpp"
#include "owval/kinematics/body_shape.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::compare::internal {

class BodyGates {
 public:
  // reference and candidate: the two headers (types, box); the reference's frame 0 is read
  // from reference_frames to recognise a sheet.
  BodyGates(const Trajectory& reference, const Trajectory& candidate, FrameSource& reference_frames,
            const ParityGates& gates);
  // One pair of frames at the same time; box_scale_cu: the reference box's largest extent.
  void Observe(const FrameRef& reference, const FrameRef& candidate, double box_scale_cu);
  // The scene's gates, decided, appended to the report.
  void AddGates(ParityReport* report);

 private:
  bool worm_ = false, membrane_ = false;
  void ObserveRings(const kinematics::BodyShape& reference, const kinematics::BodyShape& candidate,
                    double reference_time_s);
  Gate com_, span_, diameter_, ring_, membrane_gate_;
  void FindBonds(const Trajectory& reference, FrameSource& reference_frames);
  void ObserveBonds(const FrameRef& reference, const FrameRef& candidate);
  void AddBondGate(ParityReport* report);
  Gate bond_;
  // Elastic pairs within 1.5 spacings at the reference's frame 0, at most 32 a particle.
  std::vector<std::array<std::size_t, 2>> bonds_;
  double bond_spacing_cu_ = 0;  // the body's spacing there
  std::size_t worst_bond_ = 0;
  double worst_bond_time_s_ = 0, worst_bond_reference_cu_ = 0, worst_bond_candidate_cu_ = 0;
  int worst_ring_bin_ = 0;  // Sibernetic's bin (51..149) of the worst ring
  double worst_ring_time_s_ = 0, worst_ring_reference_cu_ = 0, worst_ring_candidate_cu_ = 0;
  std::vector<std::size_t> liquid_, elastic_;
  double last_reference_fraction_ = 0, last_candidate_fraction_ = 0;
};

}  // namespace owval::compare::internal
