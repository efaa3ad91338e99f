#include "owval/compare/stability.hpp"

#include <cmath>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"

namespace owval::compare {
namespace {

bool Outside(const Box& box, const float* x, double tolerance) {
  for (int a = 0; a < 3; ++a)
    if (x[a] < box.lower(a) - tolerance || x[a] > box.upper(a) + tolerance) return true;
  return false;
}

std::string Describe(const char* name, const ViolationCount& v) {
  std::ostringstream s;
  s << "  " << name << ": " << v.count;
  if (v.first_frame) s << " (first at frame " << *v.first_frame << ")";
  s << "\n";
  return s.str();
}

nlohmann::json ToJson(const ViolationCount& v) {
  return {
      {"count", v.count},
      {"first_frame", v.first_frame ? nlohmann::json(*v.first_frame) : nlohmann::json(nullptr)}};
}

}  // namespace

void ViolationCount::Add(std::size_t frame, std::size_t n) {
  count += n;
  if (!first_frame) first_frame = frame;
}

bool StabilityReport::pass() const {
  return non_finite.count == 0 && outside_box.count == 0 && blow_up.count == 0 &&
         density_out_of_range.count == 0;
}

StabilityOptions LongRunStabilityOptions() {
  StabilityOptions o;
  o.density_min = 700, o.density_max = 1300;
  o.density_outside_fraction = 0.01;
  o.density_liquid_only = true;
  return o;
}

std::string DescribeStability(const StabilityOptions& o) {
  std::string text = "NaN, escapes (over " + FormatNumber(o.box_tolerance_cu) +
                     " cu outside the box), kinetic blow-up (mean speed over " +
                     FormatNumber(o.speed_limit_m_s) + " m/s), density " +
                     FormatNumber(o.density_min) + "-" + FormatNumber(o.density_max) + " kg/m^3";
  const std::string checked = o.density_liquid_only ? "the liquid particles" : "the particles";
  if (o.density_outside_fraction == 0) return text + " for every one of " + checked;
  return text + " with at most " + FormatNumber(100 * o.density_outside_fraction) + "% of " +
         checked + " outside";
}

namespace {
// A gate's threshold that is NaN, infinite or out of range would let every frame pass (every
// comparison with NaN is false): refused as bad input instead.
void RequireThreshold(bool in_range, const char* name, double value, const char* expected) {
  if (in_range && std::isfinite(value)) return;
  throw InputError(std::string(name) + ": expected " + expected + ", found " +
                   FormatNumber(value, 6));
}
}  // namespace

StabilityMonitor::StabilityMonitor(const Box& box, std::vector<float> type,
                                   const StabilityOptions& options)
    : box_(box), type_(std::move(type)), o_(options) {
  RequireThreshold(o_.box_tolerance_cu >= 0, "box tolerance", o_.box_tolerance_cu, "cu >= 0");
  RequireThreshold(o_.speed_limit_m_s > 0, "speed limit", o_.speed_limit_m_s, "m/s > 0");
  RequireThreshold(o_.simulation_scale > 0, "simulation scale", o_.simulation_scale, "m/cu > 0");
  RequireThreshold(o_.density_min >= 0, "density minimum", o_.density_min, "kg/m^3 >= 0");
  RequireThreshold(o_.density_max > o_.density_min, "density maximum", o_.density_max,
                   "kg/m^3 above the minimum");
  RequireThreshold(o_.density_outside_fraction >= 0 && o_.density_outside_fraction <= 1,
                   "density outside fraction", o_.density_outside_fraction, "0 to 1");
  for (std::size_t p = 0; p < type_.size(); ++p) {
    if (KindOf(type_[p]) != ParticleKind::kBoundary) moving_.push_back(p);
    if (!o_.density_liquid_only || KindOf(type_[p]) == ParticleKind::kLiquid)
      density_checked_.push_back(p);
  }
}

// Mean speed of the moving particles (m/s): from velocities when present, otherwise from the
// displacement since the previous frame.
double StabilityMonitor::MeanSpeed(double time_s, const float* x, const float* v) const {
  if (moving_.empty()) return 0;
  double sum = 0;
  for (std::size_t p : moving_) {
    double v2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double va = v ? v[p * 3 + a]
                          : (x[p * 3 + a] - previous_[p * 3 + a]) * o_.simulation_scale /
                                (time_s - previous_time_s_);
      v2 += va * va;
    }
    sum += std::sqrt(v2);
  }
  return sum / double(moving_.size());
}

void StabilityMonitor::Observe(double time_s, const float* x, const float* v, const float* rho) {
  const std::size_t f = report_.frames++;
  StabilityReport& r = report_;
  if (f == 0) r.density_checked = rho != nullptr, r.velocities_from_positions = v == nullptr;
  std::size_t bad = 0, outside = 0;
  for (std::size_t p = 0; p < type_.size(); ++p) {
    const float* xp = x + 3 * p;
    if (!std::isfinite(xp[0]) || !std::isfinite(xp[1]) || !std::isfinite(xp[2])) {
      ++bad;
    } else if (Outside(box_, xp, o_.box_tolerance_cu)) {
      ++outside;
    }
  }
  if (bad) r.non_finite.Add(f, bad);
  if (outside) r.outside_box.Add(f, outside);
  if (v || f > 0) {
    const double speed = MeanSpeed(time_s, x, v);
    if (std::isfinite(speed)) r.max_mean_speed_m_s = std::max(r.max_mean_speed_m_s, speed);
    if (!(speed <= o_.speed_limit_m_s)) r.blow_up.Add(f);
  }
  if (!v) previous_.assign(x, x + 3 * type_.size()), previous_time_s_ = time_s;
  if (!rho) return;
  std::size_t out = 0;
  const std::size_t checked = density_checked_.size();
  for (std::size_t p : density_checked_)
    if (!(rho[p] >= o_.density_min && rho[p] <= o_.density_max)) ++out;
  const double fraction = checked ? double(out) / double(checked) : 0;
  r.max_density_outside_fraction = std::max(r.max_density_outside_fraction, fraction);
  if (out && fraction > o_.density_outside_fraction) r.density_out_of_range.Add(f, out);
}

void StabilityMonitor::Observe(const FrameRef& frame) {
  const Trajectory& t = frame.trajectory;
  const std::size_t n = t.particle_count(), f = frame.frame;
  Observe(t.time_s[f], t.position(f, 0), t.has_velocities() ? &t.velocities[f * n * 3] : nullptr,
          t.has_density() ? &t.density[f * n] : nullptr);
}

StabilityReport CheckStability(FrameSource& frames, const StabilityOptions& o) {
  frames.ReadFields();
  const Trajectory& header = frames.header();
  StabilityMonitor monitor(header.box, header.type, o);
  for (std::size_t f = 0; f < frames.frame_count(); ++f) monitor.Observe(frames.Frame(f));
  StabilityReport r = monitor.report();
  if (frames.frame_count() == 0) r.velocities_from_positions = true;  // as a whole empty read
  return r;
}

StabilityReport CheckStability(const Trajectory& t, const StabilityOptions& o) {
  const auto frames = MemoryFrameSource(t);
  StabilityReport r = CheckStability(*frames, o);
  r.density_checked = t.has_density();
  r.velocities_from_positions = !t.has_velocities();
  return r;
}

nlohmann::json StabilityReport::ToJson() const {
  return {{"non_finite", compare::ToJson(non_finite)},
          {"outside_box", compare::ToJson(outside_box)},
          {"kinetic_energy_blow_up", compare::ToJson(blow_up)},
          {"density_out_of_range", compare::ToJson(density_out_of_range)},
          {"density_checked", density_checked},
          {"speed_from_finite_differences", velocities_from_positions},
          {"max_mean_speed_m_s", max_mean_speed_m_s},
          {"frames", frames},
          {"max_density_outside_fraction", max_density_outside_fraction},
          {"pass", pass()}};
}

std::string StabilityReport::ToTable() const {
  std::ostringstream s;
  s << "stability: " << (pass() ? "PASS" : "FAIL") << "\n";
  s << Describe("NaN/Inf particle-frames", non_finite)
    << Describe("outside-box particle-frames", outside_box) << Describe("blow-up frames", blow_up);
  if (density_checked)
    s << Describe("density out of range", density_out_of_range)
      << "  worst frame's fraction of particles outside the density range: "
      << max_density_outside_fraction * 100 << "%\n";
  else
    s << "  density: not in this file (not checked)\n";
  s << "  max mean speed: " << max_mean_speed_m_s << " m/s"
    << (velocities_from_positions ? " (from positions)" : "") << "\n";
  return s.str();
}

std::string StabilityReport::FailureLine() const {
  if (pass()) return "";
  std::ostringstream s;
  s << "stability gate failed:";
  const char* separator = " ";
  auto add = [&](const char* name, const ViolationCount& v) {
    if (v.count == 0) return;
    s << separator << v.count << " " << name;
    if (v.first_frame) s << " (first at frame " << *v.first_frame << ")";
    separator = ", ";
  };
  add("NaN/Inf particle-frames", non_finite);
  add("outside-box particle-frames", outside_box);
  add("blow-up frames", blow_up);
  add("density-out-of-range particle-frames", density_out_of_range);
  return s.str();
}

IncompressibilityMonitor::IncompressibilityMonitor(const Trajectory& header, std::size_t frames,
                                                   bool has_density,
                                                   const IncompressibilityOptions& o)
    : o_(o) {
  RequireThreshold(o_.rest_density > 0, "rest density", o_.rest_density, "kg/m^3 > 0");
  RequireThreshold(o_.limit > 0, "limit", o_.limit, "> 0");
  if (!has_density)
    throw InputError(
        "this trajectory carries no density (Sibernetic's position_buffer.txt never does); "
        "use an owval HDF5 trajectory from `owval run`");
  liquid_ = GroupIndices(header, "liquid");
  report_.liquid_particles = liquid_.size();
  report_.limit = o.limit;
  first_ = o.skip_first_frame && frames > 1 ? 1 : 0;
}

void IncompressibilityMonitor::Observe(std::size_t index, const FrameRef& frame) {
  if (index < first_) return;
  const Trajectory& t = frame.trajectory;
  const float* rho = &t.density[frame.frame * t.particle_count()];
  ++report_.frames;
  for (std::size_t p : liquid_) {
    const double dev = std::abs(rho[p] / o_.rest_density - 1);
    sum_ += dev;
    ++count_;
    if (!(dev <= report_.max_deviation)) {
      report_.max_deviation = dev;
      report_.worst_frame = index;
      report_.worst_particle = p;
    }
  }
}

IncompressibilityReport IncompressibilityMonitor::report() const {
  IncompressibilityReport r = report_;
  r.mean_deviation = count_ ? sum_ / double(count_) : 0;
  return r;
}

IncompressibilityReport CheckIncompressibility(const Trajectory& t,
                                               const IncompressibilityOptions& o) {
  IncompressibilityMonitor monitor(t, t.frame_count(), t.has_density(), o);
  for (std::size_t f = 0; f < t.frame_count(); ++f) monitor.Observe(f, {t, f});
  return monitor.report();
}

IncompressibilityReport CheckIncompressibility(FrameSource& frames,
                                               const IncompressibilityOptions& o) {
  frames.ReadFields();
  const std::size_t count = frames.frame_count();
  IncompressibilityMonitor monitor(frames.header(), count,
                                   count > 0 && frames.Frame(0).trajectory.has_density(), o);
  for (std::size_t f = 0; f < count; ++f) monitor.Observe(f, frames.Frame(f));
  return monitor.report();
}

nlohmann::json IncompressibilityReport::ToJson() const {
  return {{"liquid_particles", liquid_particles},
          {"frames", frames},
          {"mean_abs_density_deviation", mean_deviation},
          {"max_abs_density_deviation", max_deviation},
          {"worst_frame", worst_frame ? nlohmann::json(*worst_frame) : nlohmann::json(nullptr)},
          {"worst_particle",
           worst_particle ? nlohmann::json(*worst_particle) : nlohmann::json(nullptr)},
          {"limit", limit},
          {"pass", pass()}};
}

std::string IncompressibilityReport::ToTable() const {
  std::ostringstream s;
  s << "incompressibility: " << (pass() ? "PASS" : "FAIL") << " (limit " << limit * 100 << "%)\n";
  s << "  liquid particles " << liquid_particles << ", frames " << frames << "\n";
  s << "  mean |rho/rho0 - 1| " << mean_deviation * 100 << "%, max " << max_deviation * 100 << "%";
  if (worst_frame) s << " (frame " << *worst_frame << ", particle " << *worst_particle << ")";
  s << "\n";
  return s.str();
}

}  // namespace owval::compare
