#pragma once
// The worm's gates (DD001, issue 15), added to quick-test and validate when the run is a worm:
//  - quick-test: the directory holds a .wcon that a WCON reader accepts;
//  - both: every worm side file in the directory (each .wcon, worm_motion_log.txt[.gz], .zarr
//    store) describes the candidate's trajectory, recomputed from its particles
//    (kinematics/side_files.hpp): a side file is what other tools read, and one copied from the
//    reference or another run beside a worm that does not swim passed quick-test;
//  - validate: Tier-3, each kinematic metric of the candidate against Palyanov et al. 2018's
//    baseline within +-15% (kinematics/baseline.hpp; the speed forward), and the candidate's
//    kinematics within 5% of the reference's (the speed signed: a worm going backwards is not
//    the reference's).
#include <filesystem>
#include <vector>

#include "owval/ci/gates.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::ci::internal {

// `candidate`: the directory's candidate trajectory (empty when it has none: the side files are
// then unchecked and their gates fail).
// The side files' gates alone (none when the directory holds no side file): the PR checklist's
// item 3 holds a worm candidate's side files to it without requiring a WCON.
std::vector<GateResult> WormSideFileGates(const std::filesystem::path& directory,
                                          const std::filesystem::path& candidate);
std::vector<GateResult> WormQuickTestGates(const std::filesystem::path& directory,
                                           const std::filesystem::path& candidate);
// The kinematics of every frame, observed as validate read them (kinematics::Analyser: memory
// a few doubles a frame, not the skeletons); reference: null when the reference is not a worm.
// Finished here, the candidate's first (an InputError from either, e.g. a frame's skeleton of
// fewer than 2 points, leaves validate as Analyse's did).
// candidate_frames: the candidate's trajectory, read again frame by frame in step with each side
// file (memory: one frame and one time point, whatever the run's length).
std::vector<GateResult> WormValidateGates(const std::filesystem::path& directory,
                                          const kinematics::Analyser* reference,
                                          const kinematics::Analyser& candidate,
                                          FrameSource& candidate_frames);

}  // namespace owval::ci::internal
