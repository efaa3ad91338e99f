#include "caller_reference.hpp"

#include <cmath>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"

namespace owval::ci::internal {

std::filesystem::path RunFile(const std::filesystem::path& dir, const std::string& stem) {
  std::filesystem::path found;
  for (const char* extension : {".h5", ".txt", ".txt.gz"}) {
    const std::filesystem::path file = dir / (stem + extension);
    std::error_code error;
    if (!std::filesystem::exists(file, error)) continue;
    if (!found.empty())
      throw InputError(dir.string(), 0,
                       "holds both " + found.filename().string() + " and " +
                           file.filename().string() + "; expected one " + stem);
    found = file;
  }
  return found;
}

std::string DifferenceFromCallersReference(FrameSource& got, FrameSource& wanted) {
  const Trajectory& header = got.header();
  const Trajectory& expected = wanted.header();
  if (header.particle_count() != expected.particle_count())
    return std::to_string(header.particle_count()) + " particles, the caller's reference has " +
           std::to_string(expected.particle_count());
  if (header.frame_count() != expected.frame_count())
    return std::to_string(header.frame_count()) + " frames, the caller's reference has " +
           std::to_string(expected.frame_count());
  const std::size_t values = 3 * expected.particle_count();
  for (std::size_t f = 0; f < expected.frame_count(); ++f) {
    if (std::abs(header.time_s[f] - expected.time_s[f]) > 1e-9 + 1e-6 * expected.time_s[f])
      return "frame " + std::to_string(f) + " is at " + FormatNumber(header.time_s[f]) +
             " s, the caller's reference at " + FormatNumber(expected.time_s[f]) + " s";
    const FrameRef frame = got.Frame(f);
    const FrameRef reference = wanted.Frame(f);
    const float* x = frame.trajectory.position(frame.frame, 0);
    const float* y = reference.trajectory.position(reference.frame, 0);
    for (std::size_t k = 0; k < values; ++k)
      if (!(std::abs(double(x[k]) - double(y[k])) <= 1e-3))
        return "particle " + std::to_string(k / 3) + " differs by " +
               FormatNumber(std::abs(double(x[k]) - double(y[k]))) + " cu at frame " +
               std::to_string(f);
  }
  return "";
}

}  // namespace owval::ci::internal
