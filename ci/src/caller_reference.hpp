#pragma once
// Whether an artifact directory's reference is the caller's (the checklist's item 2, ci
// validate's first gate): a directory's own reference could be its candidate under another name,
// and every parity gate would then judge the candidate against itself.
#include <filesystem>
#include <string>

#include "owval/trajectory/frame_source.hpp"

namespace owval::ci::internal {

// What ci quick-test, ci validate and the checklist read, as their refusals name it (this header
// is ci's internal one).
inline constexpr const char* kArtifactDirectory =
    "a directory of PR artifacts (reference.*, candidate.*)";

// What quick-test, validate and the checklist say of a run whose own record marks it partial
// (owval writes an interrupted or blown-up run under a .partial name, with HDF5 attribute
// partial = 1): not a result, whatever its frames show.
inline constexpr const char* kPartialRun =
    "partial: its own record says the run was interrupted, or stopped on a NaN, before it "
    "finished";

// The directory's run named `stem` ("reference" or "candidate"): STEM.h5, STEM.txt or
// STEM.txt.gz, empty when there is none. Two of them are bad input (InputError naming the
// directory): which one is the run would be a guess, and a good candidate.h5 beside a failing
// candidate.txt was judged ready.
std::filesystem::path RunFile(const std::filesystem::path& dir, const std::string& stem);

// Why `got` is not `wanted`, or empty: the same particles and frame times, every position within
// 1e-3 cu (a text file prints six or seven digits; another run differs by far more). Both are
// read frame by frame, side by side.
std::string DifferenceFromCallersReference(FrameSource& got, FrameSource& wanted);

}  // namespace owval::ci::internal
