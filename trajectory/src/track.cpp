#include "owval/trajectory/track.hpp"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

double FrameInterval(const std::vector<double>& time_s) {
  return time_s.size() > 1 ? (time_s.back() - time_s.front()) / double(time_s.size() - 1)
                           : std::numeric_limits<double>::infinity();
}

}  // namespace

const char* AxisName(Axis axis) {
  switch (axis) {
    case Axis::kX:
      return "x";
    case Axis::kY:
      return "y";
    case Axis::kZ:
      return "z";
  }
  return "?";
}

Axis ParseAxisName(const std::string& name) {
  if (name == "x") return Axis::kX;
  if (name == "y") return Axis::kY;
  if (name == "z") return Axis::kZ;
  throw InputError("unknown axis '" + name + "': expected x, y or z");
}

std::string Track::Describe() const {
  return (group.empty() ? "particle " + std::to_string(particle) : group + " centroid") + " " +
         AxisName(axis);
}

void Track::Validate(const Trajectory& t) const {
  if (!group.empty()) {
    GroupIndices(t, group);  // throws for an unknown or empty group
    return;
  }
  if (particle >= t.particle_count())
    throw InputError("tracked particle " + std::to_string(particle) +
                     " does not exist (the trajectory has " + std::to_string(t.particle_count()) +
                     " particles)");
}

std::vector<double> Track::Series(const Trajectory& t) const {
  Validate(t);
  const int a = static_cast<int>(axis);
  if (!group.empty()) return CentroidSeries(t, GroupIndices(t, group), a);
  return ParticleSeries(t, particle, a);
}

std::vector<double> Track::Series(FrameSource& frames) const {
  Validate(frames.header());
  std::vector<double> series;
  series.reserve(frames.frame_count());
  for (std::size_t f = 0; f < frames.frame_count(); ++f) {
    const FrameRef x = frames.Frame(f);
    series.push_back(ValueAt(x.trajectory, x.frame));
  }
  return series;
}

double Track::ValueAt(const Trajectory& t, std::size_t frame) const {
  Validate(t);
  if (frame >= t.frame_count())
    throw InputError("frame " + std::to_string(frame) + " does not exist (the trajectory has " +
                     std::to_string(t.frame_count()) + " frames)");
  const int a = static_cast<int>(axis);
  if (!group.empty()) return Centroid(t, frame, GroupIndices(t, group))[a];
  return t.coordinate(frame, particle, a);
}

nlohmann::json Track::ToJson() const {
  nlohmann::json j = {{"axis", AxisName(axis)}};
  if (group.empty()) {
    j["particle"] = particle;
  } else {
    j["group"] = group;
  }
  return j;
}

Track Track::FromJson(const nlohmann::json& j, const std::string& where) {
  Track t;
  if (!j.is_object()) throw InputError(where, 0, "\"track\": expected an object");
  if (j.contains("particle")) {
    const nlohmann::json& p = j["particle"];
    if (!p.is_number_unsigned())
      throw InputError(where, 0, "\"track.particle\": expected a non-negative integer");
    t.particle = p.get<std::size_t>();
  }
  if (j.contains("group")) {
    if (!j["group"].is_string()) throw InputError(where, 0, "\"track.group\": expected a string");
    t.group = j["group"].get<std::string>();
    if (!t.group.empty() && t.group != "elastic" && t.group != "liquid" && t.group != "all")
      throw InputError(where, 0, "\"track.group\": expected elastic, liquid or all");
  }
  if (j.contains("axis")) {
    if (!j["axis"].is_string()) throw InputError(where, 0, "\"track.axis\": expected x, y or z");
    try {
      t.axis = ParseAxisName(j["axis"].get<std::string>());
    } catch (const InputError&) {
      throw InputError(where, 0, "\"track.axis\": expected x, y or z");
    }
  }
  return t;
}

std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(const Trajectory& ref,
                                                                  const Trajectory& cand,
                                                                  std::size_t* near_misses) {
  return PairFramesByTime(ref.time_s, cand.time_s, near_misses);
}

std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(const std::vector<double>& ref,
                                                                  const std::vector<double>& cand,
                                                                  std::size_t* near_misses) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  const double finer = std::min(FrameInterval(ref), FrameInterval(cand));
  // Rounding of the times (a float time column, a printed time step) is far below 1% of an
  // interval; half an interval is where a frame of the other run starts to be nearer.
  const double tolerance = std::isfinite(finer) ? finer / 100 : 1e-12;
  const double near = std::isfinite(finer) ? finer / 2 : 1e-12;
  std::size_t c = 0, missed = 0;
  for (std::size_t f = 0; f < ref.size(); ++f) {
    const double t = ref[f];
    while (c + 1 < cand.size() && std::abs(cand[c + 1] - t) <= std::abs(cand[c] - t)) ++c;
    if (c >= cand.size()) continue;
    const double apart = std::abs(cand[c] - t);
    if (apart <= tolerance)
      pairs.emplace_back(f, c);
    else if (apart < near)
      ++missed;
  }
  if (near_misses) *near_misses = missed;
  return pairs;
}

}  // namespace owval
