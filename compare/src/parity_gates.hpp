#pragma once
// Each gate of the parity report decided from the reduction of the paired frames (PairReducer),
// the options' thresholds and the report's header; each appends its Gate to the report. What
// each measures and why: the comment above its definition (parity_gates.cpp) and
// docs/checklist.md's gate table.
#include <cstddef>
#include <vector>

#include "owval/compare/parity.hpp"
#include "pair_reducer.hpp"

namespace owval::compare::internal {

// The tracked quantity at the gated frames: its scalar, its 3-D position, and the groups'
// centroids at sampled frames.
void GateFrames(const Trajectory& ref, const Pairs& pairs, const std::vector<std::size_t>& gated,
                const ParityOptions& o, ParityReport* r);
void GateFramesPosition(const Pairs& pairs, const std::vector<std::size_t>& gated,
                        const PairReducer& reduced, const ParityOptions& o, ParityReport* r);
void GateSampledGroups(const Pairs& pairs, const std::vector<std::size_t>& gated,
                       const PairReducer& reduced, const ParityOptions& o, ParityReport* r);

// The runs' time bases: the common window, gaps between paired frames, the candidate's intervals.
void GateWindow(const Trajectory& ref, const ParityOptions& o, ParityReport* r);
void GateSampling(const Trajectory& ref, const Pairs& pairs, const ParityOptions& o,
                  ParityReport* r);
void GateTimeBase(const Trajectory& cand, const ParityOptions& o, ParityReport* r);
void GateSamplingOscillation(const Trajectory& ref, const Pairs& pairs, const ParityOptions& o,
                             ParityReport* r);

// The tracked signal's oscillation, and each group's drift (GroupDrift).
void GateOscillation(const ParityOptions& o, ParityReport* r);
void GateGroups(const ParityOptions& o, ParityReport* r);

// Particle by particle: the worst of each kind, the first frame, the walls, stale frames, types.
void GateWorstParticles(const PairReducer& reduced, const ParityOptions& o, ParityReport* r);
void GateInitialState(const Trajectory& ref, const PairReducer& reduced, const ParityOptions& o,
                      ParityReport* r);
void GateBoundaryFixed(const Trajectory& ref, const PairReducer& reduced, const ParityOptions& o,
                       ParityReport* r);
void GateStaleFrames(const PairReducer& reduced, ParityReport* r);
void GateParticleTypes(const Trajectory& ref, const Trajectory& cand, ParityReport* r);

// How the runs' particles meet and pack: closest approach, held pairs, the liquid's packing.
void GateClosestApproach(const Trajectory& ref, const PairReducer& reduced, const ParityOptions& o,
                         ParityReport* r);
void GateHeldPair(const Trajectory& ref, const Pairs& pairs, const PairReducer& reduced,
                  const ParityOptions& o, ParityReport* r);
void GateLiquidPacking(const PairReducer& reduced, const ParityOptions& o, ParityReport* r);

// The forces, seen in the accelerations between frames, and the frames between paired ones.
void GateAcceleration(const PairReducer& reduced, const ParityOptions& o, ParityReport* r);
void GateAccelerationStencil(const PairReducer& reduced, const ParityOptions& o, ParityReport* r);
void GateUnpairedFrames(const PairReducer& reduced, const ParityOptions& o, ParityReport* r);

// Not a gate: the tracked signals' metrics (period, half-amplitude, equilibrium) and the frame
// gates' scale, into the report, before the gates read them.
void MeasureSignals(const PairReducer& reduced, const ParityOptions& o, ParityReport* r);

}  // namespace owval::compare::internal
