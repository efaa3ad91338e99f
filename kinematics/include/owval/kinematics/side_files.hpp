#pragma once
// A worm run's side files against its trajectory. A WCON (tracker-commons) or
// worm_motion_log.txt (Sibernetic's midline log, midline.hpp) is what other tools and `owval
// kinematics FILE` read, but it is the producer's claim about the run, not the run: a port that
// wrote the reference's midline log or WCON beside a worm that does not swim, a WCON in µm
// labelled mm, or one whose "t" is scaled, would show kinematics its trajectory does not have.
// So a side file must describe the trajectory it sits beside, recomputed from its particles:
//  - the same time points, each within 1% of the trajectory's mean frame interval (the rounding
//    allowance by which every owval command pairs frames by time, trajectory's PairFramesByTime);
//  - per time point the same number of skeleton points (non-empty midline bins, head first);
//  - every point's x and y within 1e-5 of the coordinate's magnitude (a midline from
//    full-precision floats against one from 6-significant-digit prints: 5e-6 each, as the
//    initial_state gate allows) plus 1e-3 cu = 7.4e-6 mm (the tolerance by which the caller's
//    reference is the directory's), in mm;
//  - a WCON's centroid (cx, cy, when it has one) within the same allowance of the trajectory's:
//    the mean of the elastic particles in the body plane (cx = simulation z, cy = simulation x,
//    in mm), as TrackPointAt computes it for WconWriter. A centroid written from another run or
//    in µm labelled mm is as wrong as a skeleton would be.
// Memory is bounded by the particles, never by the run's length: the trajectory is read frame by
// frame and each frame's skeleton and centroid compared with the side file's time point of the
// same index, then dropped; the midline log is read line by line and the WCON time point by time
// point (WconReader).
// Measured on Sibernetic's 0.6 s worm run (docs/worm.md, "Side files"): its own worm_motion_log
// against its 6-digit position_buffer, worst 0.113 of the allowance.
#include <filesystem>
#include <string>

#include "owval/kinematics/skeleton.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/worm_formats.hpp"

namespace owval::kinematics {

struct TrackAgreement {
  bool agrees = false;
  double worst_fraction_of_allowance = 0;  // worst point's distance / its allowance
  std::string detail;                      // one line: what was compared, or the first mismatch
};

// A track in memory (an edited one, a test's) against the trajectory read frame by frame.
TrackAgreement CompareWithTrajectory(const WormTrack& track, FrameSource& trajectory);
// A WCON file, read time point by time point (WconReader), against the trajectory.
TrackAgreement CompareWconWithTrajectory(const std::filesystem::path& wcon,
                                         FrameSource& trajectory);
// The same with a WCON already parsed, read from its first time point (quick-test parses the
// file once for its readability gate and this one).
TrackAgreement CompareWconWithTrajectory(WconReader& wcon, FrameSource& trajectory);
// worm_motion_log.txt[.gz], read line by line as ReadWormMotionLog reads it, against the
// trajectory (the log has no centroid).
TrackAgreement CompareWormMotionLogWithTrajectory(const std::filesystem::path& log,
                                                  FrameSource& trajectory);

// An OME-Zarr store (body/positions in µm) against the trajectory it was converted from: the same
// frame count, times (1% of the mean interval), type codes (1e-5 relative, as particle_types) and
// every coordinate within 1e-5 of its magnitude plus 1e-3 cu (at Sibernetic's float scale,
// 7.39999905e-3 µm). The trajectory is read frame by frame. A store recording another
// simulation_scale_m than Sibernetic's is refused (InputError naming its .zattrs): its µm are not
// the trajectory's; positions in another length unit are converted by the reader.
TrackAgreement CompareWithTrajectory(OmeZarrReader& store, FrameSource& trajectory);

// worm_motion_log.txt as a track: per line, time (s) and the non-empty bins' (X:, Y:) means
// (simulation z, x in mm: the WCON body plane); a bin whose three means print 0 is empty, as
// Sibernetic prints empty bins. Plain or gzip-compressed. InputError naming the file and line on
// a malformed line.
WormTrack ReadWormMotionLog(const std::filesystem::path& path);

}  // namespace owval::kinematics
