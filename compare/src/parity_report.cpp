// The parity report's own output: JSON, Markdown and the terminal's table.
#include <sstream>

#include "owval/base/format.hpp"
#include "owval/compare/metrics_json.hpp"
#include "owval/compare/parity.hpp"

namespace owval::compare {

const Gate* ParityReport::gate(const std::string& name) const {
  for (const Gate& g : gates)
    if (g.name == name) return &g;
  return nullptr;
}

namespace {
nlohmann::json Opt(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

// The sampled frames' parity, one object a frame.
nlohmann::json FramesJson(const std::vector<FrameParity>& frames) {
  nlohmann::json frames_json = nlohmann::json::array();
  for (const FrameParity& f : frames)
    frames_json.push_back({{"reference_frame", f.reference_frame},
                           {"candidate_frame", f.candidate_frame},
                           {"time_s", f.time_s},
                           {"reference_value_cu", f.reference_value},
                           {"candidate_value_cu", f.candidate_value},
                           {"relative_difference", f.relative_difference},
                           {"pass", f.pass}});
  return frames_json;
}

// Each group's drift, one object a group; the pose fields null for a group without a pose.
nlohmann::json DriftJson(const std::vector<GroupDrift>& drift) {
  nlohmann::json drift_json = nlohmann::json::array();
  for (const GroupDrift& d : drift)
    drift_json.push_back(
        {{"group", d.group},
         {"final_centroid_distance_cu", d.final_centroid_distance_cu},
         {"max_centroid_distance_cu", d.max_centroid_distance_cu},
         {"max_extent_difference_of_box", d.max_extent_difference_fraction},
         {"final_extent_ratio_xyz",
          {d.final_extent_ratio[0], d.final_extent_ratio[1], d.final_extent_ratio[2]}},
         {"final_rotation_deg", d.has_pose ? nlohmann::json{{"reference", d.final_rotation_deg[0]},
                                                            {"candidate", d.final_rotation_deg[1]}}
                                           : nlohmann::json()},
         {"final_body_extent_ratio_xyz",
          d.has_pose ? nlohmann::json{d.final_body_extent_ratio[0], d.final_body_extent_ratio[1],
                                      d.final_body_extent_ratio[2]}
                     : nlohmann::json()}});
  return drift_json;
}
}  // namespace

// One key a field: a table, kept whole so that the JSON's shape reads in one place.
nlohmann::json ParityReport::ToJson() const {
  return {{"subject", subject},
          {"scale_cu", scale},
          {"scale_given", scale_given},
          {"reference_range_cu", reference_range},
          {"box_scale_cu", box_scale_cu},
          {"paired_frames", paired_frames},
          {"common_window_s", {common_window_start_s, common_window_end_s}},
          {"gates", compare::ToJson(gates)},
          {"failed_gates", FailedGates()},
          {"frames", FramesJson(frames)},
          {"failing_frames", failing_frames},
          {"per_particle_distance_cu",
           {{"initial", l2_initial_cu}, {"mean", l2_mean_cu}, {"final", l2_final_cu}}},
          {"group_drift", DriftJson(drift)},
          {"reference_metrics", compare::ToJson(reference_metrics)},
          {"candidate_metrics", compare::ToJson(candidate_metrics)},
          {"gaps",
           {{"period_relative", Opt(period_gap)},
            {"half_amplitude_relative", Opt(half_amplitude_gap)},
            {"equilibrium_cu", Opt(equilibrium_gap_cu)}}},
          {"reference_crossings_all_frames", reference_crossings_all_frames},
          {"reference_period_all_frames_s", Opt(reference_period_all_frames_s)},
          {"misaligned_pairs", misaligned_pairs},
          {"reference_partial", reference_partial},
          {"candidate_partial", candidate_partial},
          {"pass", pass()}};
}

namespace {
std::string PartialNotes(const ParityReport& r, const char* prefix) {
  std::string notes;
  for (const auto& [side, partial] :
       {std::pair{"reference", r.reference_partial}, std::pair{"candidate", r.candidate_partial}})
    if (partial)
      notes += std::string(prefix) + "note: the " + side +
               " is partial (an interrupted run's): compared over the frames it has\n";
  return notes;
}
}  // namespace

std::string ParityReport::ToMarkdown() const {
  std::ostringstream s;
  s << "### Parity: " << subject << " — " << (pass() ? "PASS" : "FAIL");
  if (!pass()) s << " (failed: " << FailedGates() << ")";
  s << "\n\n- paired frames: " << paired_frames << ", common window " << common_window_start_s
    << " s to " << common_window_end_s << " s\n- frame-gate scale: " << scale
    << (scale_given ? " cu (GIVEN by the caller, --scale; the reference range is " +
                          FormatNumber(reference_range, 4) + " cu)"
                    : std::string(" cu (reference range)"))
    << "; box scale: " << box_scale_cu << " cu\n"
    << PartialNotes(*this, "- ") << "\n";
  s << GatesMarkdownTable(gates);
  return s.str();
}

std::string ParityReport::ToTable() const {
  std::ostringstream s;
  s << "parity of " << subject << ": " << (pass() ? "PASS" : "FAIL");
  if (!pass()) s << " (failed: " << FailedGates() << ")";
  s << "\n  paired frames " << paired_frames << " over " << common_window_start_s << " s to "
    << common_window_end_s << " s; frame scale " << scale << " cu"
    << (scale_given
            ? " (GIVEN by --scale; reference range " + FormatNumber(reference_range) + " cu)"
            : std::string())
    << ", box scale " << box_scale_cu << " cu\n"
    << PartialNotes(*this, "  ");
  s << GatesTextTable(gates);
  s << "  particle distance (cu): initial " << l2_initial_cu << ", mean " << l2_mean_cu
    << ", final " << l2_final_cu << "\n";
  return s.str();
}

}  // namespace owval::compare
