#include "owval/trajectory/trajectory.hpp"

#include "frame_times.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "owval/base/errors.hpp"

namespace owval {

ParticleKind KindOf(float type_code) {
  // The integer part by comparison, not by a cast: casting NaN or 1e30 to int is undefined.
  if (type_code >= 1.0f && type_code < 2.0f) return ParticleKind::kLiquid;
  if (type_code >= 2.0f && type_code < 3.0f) return ParticleKind::kElastic;
  return ParticleKind::kBoundary;
}

bool IsSiberneticTypeCode(float type_code) { return type_code >= 1.0f && type_code < 4.0f; }

const char* KindName(ParticleKind kind) {
  switch (kind) {
    case ParticleKind::kLiquid:
      return "liquid";
    case ParticleKind::kElastic:
      return "elastic";
    case ParticleKind::kBoundary:
      return "boundary";
  }
  return "?";
}

float Box::lower(int axis) const { return axis == 0 ? xmin : axis == 1 ? ymin : zmin; }
float Box::upper(int axis) const { return axis == 0 ? xmax : axis == 1 ? ymax : zmax; }
float Box::extent(int axis) const { return upper(axis) - lower(axis); }

std::size_t Trajectory::count(ParticleKind kind) const {
  return static_cast<std::size_t>(
      std::count_if(type.begin(), type.end(), [kind](float t) { return KindOf(t) == kind; }));
}

void Trajectory::CheckShape() const {
  const std::size_t cells = frame_count() * particle_count();
  if (positions.size() != cells * 3) throw std::logic_error("trajectory: positions shape mismatch");
  if (!velocities.empty() && velocities.size() != cells * 3)
    throw std::logic_error("trajectory: velocities shape mismatch");
  if (!density.empty() && density.size() != cells)
    throw std::logic_error("trajectory: density shape mismatch");
  if (!pressure.empty() && pressure.size() != cells)
    throw std::logic_error("trajectory: pressure shape mismatch");
}

void Trajectory::AppendFrame(double frame_time_s, const float* frame_positions) {
  time_s.push_back(frame_time_s);
  positions.insert(positions.end(), frame_positions, frame_positions + 3 * particle_count());
}

namespace {

// The shortest text that reads back as `value`: two times that print alike are equal.
std::string ExactSeconds(double value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end) + " s";
}

}  // namespace

void CheckFrameTimesIncrease(const std::vector<double>& time_s, const std::string& file,
                             const std::string& where) {
  for (std::size_t f = 0; f < time_s.size(); ++f)
    CheckFrameTimeFollows(f, time_s[f], f > 0 ? time_s[f - 1] : 0, file, where);
}

void CheckFrameTimeFollows(std::size_t f, double time_s, double previous_s, const std::string& file,
                           const std::string& where) {
  const std::string frame = "frame " + std::to_string(f) + "'s time " + ExactSeconds(time_s);
  if (!std::isfinite(time_s))
    throw InputError(file, 0, where + frame + " is not finite: frame times must be finite");
  if (f > 0 && !(time_s > previous_s))
    throw InputError(file, 0,
                     where + frame + " is not after frame " + std::to_string(f - 1) + "'s " +
                         ExactSeconds(previous_s) + ": frame times must increase");
}

std::vector<std::size_t> GroupIndices(const Trajectory& trajectory, const std::string& group) {
  std::vector<std::size_t> indices;
  const bool all = group == "all";
  ParticleKind kind = ParticleKind::kBoundary;
  if (group == "elastic") {
    kind = ParticleKind::kElastic;
  } else if (group == "liquid") {
    kind = ParticleKind::kLiquid;
  } else if (group == "boundary") {
    kind = ParticleKind::kBoundary;
  } else if (!all) {
    throw InputError("unknown particle group '" + group +
                     "': expected elastic, liquid, boundary or all");
  }
  for (std::size_t i = 0; i < trajectory.particle_count(); ++i) {
    const ParticleKind k = KindOf(trajectory.type[i]);
    // "all" means every particle that can move: boundary particles never do.
    if (all ? k != ParticleKind::kBoundary : k == kind) indices.push_back(i);
  }
  if (indices.empty())
    throw InputError("particle group '" + group + "' is empty in this trajectory");
  return indices;
}

std::array<double, 3> Centroid(const Trajectory& trajectory, std::size_t frame,
                               const std::vector<std::size_t>& particles) {
  std::array<double, 3> sum = {0, 0, 0};
  for (std::size_t p : particles) {
    const float* x = trajectory.position(frame, p);
    for (int a = 0; a < 3; ++a) sum[a] += x[a];
  }
  for (double& s : sum) s /= static_cast<double>(particles.size());
  return sum;
}

std::vector<double> ParticleSeries(const Trajectory& trajectory, std::size_t particle, int axis) {
  if (particle >= trajectory.particle_count())
    throw InputError("particle " + std::to_string(particle) + " does not exist (trajectory has " +
                     std::to_string(trajectory.particle_count()) + " particles)");
  std::vector<double> series(trajectory.frame_count());
  for (std::size_t f = 0; f < series.size(); ++f)
    series[f] = trajectory.coordinate(f, particle, axis);
  return series;
}

std::vector<double> CentroidSeries(const Trajectory& trajectory,
                                   const std::vector<std::size_t>& particles, int axis) {
  std::vector<double> series(trajectory.frame_count());
  for (std::size_t f = 0; f < series.size(); ++f)
    series[f] = Centroid(trajectory, f, particles)[axis];
  return series;
}

}  // namespace owval
