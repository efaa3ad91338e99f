#include "owval/compare/parity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/compare/metrics_json.hpp"

namespace owval::compare {
namespace {

const char* kAxisNames[3] = {"x", "y", "z"};

double FrameInterval(const Trajectory& t) {
  return t.frame_count() > 1 ? (t.time_s.back() - t.time_s.front()) / double(t.frame_count() - 1)
                             : 0.0;
}

std::vector<double> TrackedSeries(const Trajectory& t, const ParityOptions& o) {
  if (!o.group.empty()) return CentroidSeries(t, GroupIndices(t, o.group), o.axis);
  return ParticleSeries(t, o.particle, o.axis);
}

double MeanParticleDistance(const Trajectory& a, std::size_t fa, const Trajectory& b,
                            std::size_t fb) {
  double sum = 0;
  for (std::size_t p = 0; p < a.particle_count(); ++p) {
    const float* x = a.position(fa, p);
    const float* y = b.position(fb, p);
    sum += std::sqrt(double(x[0] - y[0]) * (x[0] - y[0]) + double(x[1] - y[1]) * (x[1] - y[1]) +
                     double(x[2] - y[2]) * (x[2] - y[2]));
  }
  return sum / double(a.particle_count());
}

void Extent(const Trajectory& t, std::size_t frame, const std::vector<std::size_t>& group,
            double out[3]) {
  for (int a = 0; a < 3; ++a) {
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (std::size_t p : group) {
      lo = std::min<double>(lo, t.coordinate(frame, p, a));
      hi = std::max<double>(hi, t.coordinate(frame, p, a));
    }
    out[a] = hi - lo;
  }
}

std::optional<GroupDrift> MeasureDrift(
    const Trajectory& ref, const Trajectory& cand, const std::string& group,
    const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  std::vector<std::size_t> members;
  try {
    members = GroupIndices(ref, group);
  } catch (const InputError&) {
    return std::nullopt;  // the scenario has no such particles
  }
  GroupDrift d;
  d.group = group;
  for (const auto& [fr, fc] : pairs) {
    const auto a = Centroid(ref, fr, members), b = Centroid(cand, fc, members);
    const double dist = std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    d.max_centroid_distance_cu = std::max(d.max_centroid_distance_cu, dist);
    d.final_centroid_distance_cu = dist;
  }
  double er[3], ec[3];
  Extent(ref, pairs.back().first, members, er);
  Extent(cand, pairs.back().second, members, ec);
  for (int a = 0; a < 3; ++a)
    d.final_extent_ratio[a] = er[a] > 0 ? ec[a] / er[a] : (ec[a] > 0 ? INFINITY : 1);
  return d;
}

std::optional<double> RelativeGap(const std::optional<double>& ref,
                                  const std::optional<double>& cand) {
  if (!ref || !cand || *ref == 0) return std::nullopt;
  return (*cand - *ref) / *ref;
}

void GateFrames(const std::vector<double>& ref_series, const std::vector<double>& cand_series,
                const Trajectory& ref,
                const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                const ParityOptions& o, ParityReport* r) {
  std::vector<std::pair<std::size_t, std::size_t>> gated;
  if (o.sample_frames.empty()) {
    gated = pairs;
  } else {
    for (std::size_t f : o.sample_frames) {
      auto it =
          std::find_if(pairs.begin(), pairs.end(), [f](const auto& p) { return p.first == f; });
      if (it == pairs.end())
        throw InputError(
            "sample frame " + std::to_string(f) + " has no candidate frame at t = " +
            (f < ref.frame_count() ? std::to_string(ref.time_s[f]) : std::string("?")) + " s");
      gated.push_back(*it);
    }
  }
  for (const auto& [fr, fc] : gated) {
    FrameParity fp{fr, fc, ref.time_s[fr], ref_series[fr], cand_series[fc], 0, true};
    fp.relative_difference = std::abs(fp.candidate_value - fp.reference_value) / r->scale;
    fp.pass = std::isfinite(fp.candidate_value) && fp.relative_difference < o.frame_threshold;
    if (!fp.pass) r->failing_frames.push_back(fr);
    r->frames.push_back(fp);
  }
  r->frames_pass = r->failing_frames.empty();
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> PairFramesByTime(const Trajectory& ref,
                                                                  const Trajectory& cand) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  const double finer = std::min(FrameInterval(ref) > 0 ? FrameInterval(ref) : INFINITY,
                                FrameInterval(cand) > 0 ? FrameInterval(cand) : INFINITY);
  const double tolerance = std::isfinite(finer) ? finer / 2 : 1e-12;
  std::size_t c = 0;
  for (std::size_t f = 0; f < ref.frame_count(); ++f) {
    const double t = ref.time_s[f];
    while (c + 1 < cand.frame_count() &&
           std::abs(cand.time_s[c + 1] - t) <= std::abs(cand.time_s[c] - t))
      ++c;
    if (c < cand.frame_count() && std::abs(cand.time_s[c] - t) < tolerance)
      pairs.emplace_back(f, c);
  }
  return pairs;
}

ParityReport CompareTrajectories(const Trajectory& ref, const Trajectory& cand,
                                 const ParityOptions& o) {
  if (ref.particle_count() != cand.particle_count())
    throw InputError("wrong particle count: the reference has " +
                     std::to_string(ref.particle_count()) + " particles, the candidate " +
                     std::to_string(cand.particle_count()));
  const auto pairs = PairFramesByTime(ref, cand);
  if (pairs.empty()) throw InputError("the reference and candidate share no frame time");
  ParityReport r;
  r.subject = (o.group.empty() ? "particle " + std::to_string(o.particle) : o.group + " centroid") +
              " " + kAxisNames[o.axis];
  r.paired_frames = pairs.size();
  const std::vector<double> ref_series = TrackedSeries(ref, o),
                            cand_series = TrackedSeries(cand, o);
  const auto [lo, hi] = std::minmax_element(ref_series.begin(), ref_series.end());
  r.scale = o.scale ? *o.scale : (*hi - *lo);
  if (!(r.scale > 0)) r.scale = 1.0;  // a constant reference: compare in absolute config units
  GateFrames(ref_series, cand_series, ref, pairs, o, &r);
  double l2_sum = 0;
  for (const auto& [fr, fc] : pairs) l2_sum += MeanParticleDistance(ref, fr, cand, fc);
  r.l2_initial_cu = MeanParticleDistance(ref, pairs.front().first, cand, pairs.front().second);
  r.l2_final_cu = MeanParticleDistance(ref, pairs.back().first, cand, pairs.back().second);
  r.l2_mean_cu = l2_sum / double(pairs.size());
  for (const char* group : {"elastic", "liquid"})
    if (auto d = MeasureDrift(ref, cand, group, pairs)) r.drift.push_back(*d);
  r.reference_metrics = MeasureSignal(ref.time_s, ref_series);
  r.candidate_metrics = MeasureSignal(cand.time_s, cand_series);
  r.period_gap = RelativeGap(r.reference_metrics.period_s, r.candidate_metrics.period_s);
  r.half_amplitude_gap =
      RelativeGap(r.reference_metrics.half_amplitude, r.candidate_metrics.half_amplitude);
  r.equilibrium_gap_cu = r.candidate_metrics.equilibrium - r.reference_metrics.equilibrium;
  r.metrics_pass =
      (!r.period_gap || std::abs(*r.period_gap) < o.period_gap_threshold) &&
      (!r.half_amplitude_gap || std::abs(*r.half_amplitude_gap) < o.amplitude_gap_threshold);
  return r;
}

namespace {
nlohmann::json Opt(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::string Pct(const std::optional<double>& v) {
  if (!v) return "n/a";
  char b[32];
  std::snprintf(b, sizeof b, "%+.3f%%", *v * 100);
  return b;
}

std::string FailingList(const std::vector<std::size_t>& frames) {
  std::ostringstream s;
  for (std::size_t i = 0; i < frames.size() && i < 20; ++i) s << (i ? ", " : "") << frames[i];
  if (frames.size() > 20) s << ", ... (" << frames.size() << " in all)";
  return s.str();
}
}  // namespace

nlohmann::json ParityReport::ToJson() const {
  nlohmann::json frames_json = nlohmann::json::array();
  for (const FrameParity& f : frames)
    frames_json.push_back({{"reference_frame", f.reference_frame},
                           {"candidate_frame", f.candidate_frame},
                           {"time_s", f.time_s},
                           {"reference_value_cu", f.reference_value},
                           {"candidate_value_cu", f.candidate_value},
                           {"relative_difference", f.relative_difference},
                           {"pass", f.pass}});
  nlohmann::json drift_json = nlohmann::json::array();
  for (const GroupDrift& d : drift)
    drift_json.push_back(
        {{"group", d.group},
         {"final_centroid_distance_cu", d.final_centroid_distance_cu},
         {"max_centroid_distance_cu", d.max_centroid_distance_cu},
         {"final_extent_ratio_xyz",
          {d.final_extent_ratio[0], d.final_extent_ratio[1], d.final_extent_ratio[2]}}});
  return {{"subject", subject},
          {"scale_cu", scale},
          {"paired_frames", paired_frames},
          {"frames", frames_json},
          {"failing_frames", failing_frames},
          {"per_particle_distance_cu",
           {{"initial", l2_initial_cu}, {"mean", l2_mean_cu}, {"final", l2_final_cu}}},
          {"group_drift", drift_json},
          {"reference_metrics", compare::ToJson(reference_metrics)},
          {"candidate_metrics", compare::ToJson(candidate_metrics)},
          {"gaps",
           {{"period_relative", Opt(period_gap)},
            {"half_amplitude_relative", Opt(half_amplitude_gap)},
            {"equilibrium_cu", Opt(equilibrium_gap_cu)}}},
          {"frames_pass", frames_pass},
          {"metrics_pass", metrics_pass},
          {"pass", pass()}};
}

std::string ParityReport::ToMarkdown() const {
  std::ostringstream s;
  s << "### Parity: " << subject << " — " << (pass() ? "PASS" : "FAIL") << "\n\n";
  s << "| check | result |\n|---|---|\n";
  s << "| frames gated (Δ/scale < threshold, scale " << scale << " cu) | "
    << frames.size() - failing_frames.size() << "/" << frames.size() << " pass |\n";
  if (!failing_frames.empty()) s << "| failing frames | " << FailingList(failing_frames) << " |\n";
  s << "| mean particle distance initial / mean / final | " << l2_initial_cu << " / " << l2_mean_cu
    << " / " << l2_final_cu << " cu |\n";
  s << "| period gap | " << Pct(period_gap) << " |\n| half-amplitude gap | "
    << Pct(half_amplitude_gap) << " |\n";
  s << "| equilibrium gap | "
    << (equilibrium_gap_cu ? std::to_string(*equilibrium_gap_cu) + " cu" : "n/a") << " |\n";
  for (const GroupDrift& d : drift)
    s << "| " << d.group << " centroid drift final / max | " << d.final_centroid_distance_cu
      << " / " << d.max_centroid_distance_cu << " cu |\n";
  return s.str();
}

std::string ParityReport::ToTable() const {
  std::ostringstream s;
  s << "parity of " << subject << ": " << (pass() ? "PASS" : "FAIL") << "\n";
  s << "  paired frames            " << paired_frames << "\n";
  s << "  frames gated             " << frames.size() << ", failing " << failing_frames.size()
    << "\n";
  if (!failing_frames.empty())
    s << "  failing frames           " << FailingList(failing_frames) << "\n";
  double worst = 0;
  for (const FrameParity& f : frames) worst = std::max(worst, f.relative_difference);
  s << "  worst |Δ|/scale          " << worst * 100 << "% (scale " << scale << " cu)\n";
  s << "  particle distance (cu)   initial " << l2_initial_cu << ", mean " << l2_mean_cu
    << ", final " << l2_final_cu << "\n";
  s << "  period gap               " << Pct(period_gap) << "\n";
  s << "  half-amplitude gap       " << Pct(half_amplitude_gap) << "\n";
  for (const GroupDrift& d : drift)
    s << "  " << d.group << " centroid drift  final " << d.final_centroid_distance_cu << " cu, max "
      << d.max_centroid_distance_cu << " cu\n";
  return s.str();
}

}  // namespace owval::compare
