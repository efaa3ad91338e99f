// The gates' thresholds by name: manifest field, command-line flag and help (kGateThresholdFields),
// and which of a caller's thresholds are looser than the defaults.
#include <string>
#include <vector>

#include "owval/base/format.hpp"
#include "owval/compare/parity.hpp"

namespace owval::compare {

using G = ParityGates;
const std::vector<GateThresholdField> kGateThresholdFields = {
    {"frame_threshold", "--threshold", &G::frame,
     "frames gate: |cand - ref| / the reference's range of the tracked scalar at each gated "
     "frame; frames.position: of its particle's (or centroid's) 3-D position on the same scale"},
    {"period_gap_threshold", "--period-gap", &G::period_gap,
     "period gate: the relative gap of the tracked signal's periods"},
    {"amplitude_gap_threshold", "--amplitude-gap", &G::amplitude_gap,
     "half_amplitude gate: the relative gap of the half-amplitudes"},
    {"min_crossings", "--min-crossings", &G::min_crossings,
     "Upward crossings both signals need for the oscillation gates"},
    {"centroid_distance_threshold", "--centroid-threshold", &G::centroid_distance,
     "centroid_distance gates (elastic, liquid) and worm.centre_of_mass: the centroids' "
     "largest distance over time, fraction of the box"},
    {"extent_threshold", "--extent-threshold", &G::extent,
     "extent gates (elastic, liquid): the largest |extent difference| per axis, fraction of "
     "the box extent"},
    {"final_distance_threshold", "--final-threshold", &G::final_distance,
     "final_distance gates (elastic, liquid): the centroids' distance at the last frame, "
     "fraction of the box"},
    {"particle_distance_threshold", "--particle-threshold", &G::particle_distance,
     "particle_distance.initial/mean/final gates: the moving particles' distances, fraction "
     "of the box"},
    {"worst_particle_threshold", "--worst-particle-threshold", &G::worst_particle,
     "worst_particle gates (elastic, liquid, boundary): one particle's largest distance, "
     "fraction of the box"},
    {"body_shape_threshold", "--body-threshold", &G::body_shape,
     "worm.span, worm.cross_section_diameter and worm.ring_diameter gates, relative"},
    {"membrane_liquid_fraction_threshold", "--membrane-threshold", &G::membrane_liquid_fraction,
     "liquid.fraction_above_membrane gate: the difference of the fractions"},
    {"bond_length_threshold", "--bond-length-threshold", &G::bond_length,
     "elastic.bond_length gate: the largest difference of a bond's length (elastic pairs within "
     "1.5 spacings at the reference's first frame), of the body's spacing"},
    {"window_threshold", "--window-threshold", &G::window,
     "window gate: the reference's duration outside the common window, fraction"},
    {"sampling_threshold", "--sampling-threshold", &G::sampling,
     "sampling gate: the longest time between paired frames that skips reference frames, "
     "fraction of the reference's duration"},
    {"sampling_period_threshold", "--sampling-period-threshold", &G::sampling_period,
     "sampling.oscillation gate: the same gap, fraction of the reference's own period"},
    {"time_base_threshold", "--time-base-threshold", &G::time_base,
     "time_base gate: a candidate frame interval's departure from the mean, fraction"},
    {"initial_state_threshold", "--initial-state-threshold", &G::initial_state,
     "initial_state gate: the candidate's worst coordinate at the reference's first frame, in "
     "units of the rounding of two 6-significant-digit prints"},
    {"closest_approach_threshold", "--closest-approach-threshold", &G::closest_approach,
     "closest_approach gate: how many times closer than the reference's closest approach two "
     "of the candidate's particles (one moving) may come"},
    {"held_pair_threshold", "--held-pair-threshold", &G::held_pair,
     "held_pair gate: how many times closer than the reference holds a pair of a kind for a "
     "tenth of the paired frames the candidate may hold one"},
    {"liquid_packing_threshold", "--liquid-packing-threshold", &G::liquid_packing,
     "liquid_packing gate: the relative gap of the liquid's mean kernel sum (median, upper "
     "quartile) to the reference's"},
    {"acceleration_threshold", "--acceleration-threshold", &G::acceleration,
     "acceleration gate: the relative gap of the moving particles' mean acceleration between "
     "frames (median, upper quartile; worst kind) to the reference's"},
    {"acceleration_stencil_threshold", "--acceleration-stencil-threshold", &G::acceleration_stencil,
     "acceleration.worst_stencil gate: the most one run's median acceleration at a stencil of "
     "three paired frames exceeds the other's nearby, relative (a frame written displaced)"},
    {"unpaired_frames_threshold", "--unpaired-frames-threshold", &G::unpaired_frames,
     "unpaired_frames gate: how far a finer candidate's frames between two paired frames stray "
     "outside the box of the pair, of the reference's fastest reach over the interval"}};

std::string GateThresholdHelp(const GateThresholdField& field) {
  return std::string(field.help) + " (default " +
         FormatNumber((ParityGates{}.*field.member).value) + ")";
}

std::vector<std::string> LoosenedThresholds(const ParityGates& gates) {
  const ParityGates defaults;
  std::vector<std::string> loosened;
  for (const GateThresholdField& field : kGateThresholdFields) {
    const Threshold& given = gates.*field.member;
    const double default_value = (defaults.*field.member).value;
    if (!(given.value <= default_value))
      loosened.push_back(std::string(field.manifest_key) + " " + FormatNumber(given.value) + " (" +
                         SourceName(given.source) + "; default " + FormatNumber(default_value) +
                         ")");
  }
  return loosened;
}

ParityGates NoLooserThanDefaults(const ParityGates& gates) {
  const ParityGates defaults;
  ParityGates out = gates;
  for (const GateThresholdField& field : kGateThresholdFields)
    if (!((gates.*field.member).value <= (defaults.*field.member).value))
      out.*field.member = defaults.*field.member;
  return out;
}

}  // namespace owval::compare
