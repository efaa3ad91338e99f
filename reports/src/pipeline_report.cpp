#include "owval/reports/pipeline_report.hpp"

#include <cmath>
#include <cstdio>

#include "owval/base/format.hpp"
#include "owval/reports/svg_plot.hpp"

namespace owval::reports {
namespace {

std::string NumOr(const std::optional<double>& v) { return v ? FormatNumber(*v, 6) : "n/a"; }

// A gap with its unit: relative gaps as percentages, absolute ones in the quantity's unit.
std::string Gap(const predict::ReconcileRow& row) {
  if (!row.gap) return "n/a";
  if (!row.gap_in_cu) return FormatPercent(*row.gap);
  return FormatNumber(*row.gap, 6) + " " + row.unit;
}

std::string Tolerance(const predict::ReconcileRow& row) {
  if (row.tolerance_kind == predict::ToleranceKind::kInformative) return "-";
  if (row.tolerance_kind == predict::ToleranceKind::kRelative)
    return "< " + FormatPercent(row.tolerance);
  return "< " + FormatNumber(row.tolerance, 6) + " " + row.unit;
}

std::string Verdict(const predict::ReconcileRow& row) {
  if (!row.pass) return "informative";
  return *row.pass ? "pass" : "FAIL";
}

void PredictionSection(const PipelineEvidence& e, Document* d) {
  d->Heading("1-3. Prediction reconciled with the reference");
  std::vector<std::vector<std::string>> rows = {
      {"quantity", "unit", "predicted", "measured (reference)", "gap", "tolerance", "result"}};
  for (const predict::ReconcileRow& r : e.reconcile.rows)
    rows.push_back({r.quantity, r.unit, NumOr(r.predicted), NumOr(r.measured), Gap(r), Tolerance(r),
                    Verdict(r)});
  d->Table(rows);
}

Series Line(const std::string& name, const std::vector<double>& t_s, const std::vector<double>& y,
            double until_s = INFINITY) {
  Series s{name, {}, {}};
  for (std::size_t i = 0; i < t_s.size() && i < y.size(); ++i)
    if (t_s[i] <= until_s) {
      s.x.push_back(t_s[i] * 1e3);
      s.y.push_back(y[i]);
    }
  return s;
}

void CandidateSection(const PipelineEvidence& e, Document* d) {
  const compare::ParityReport& p = e.parity;
  d->Heading("4. Candidate");
  d->Paragraph("Reference: " + e.reference_source + ". Candidate: " + e.candidate_source + ".");
  PlotOptions o;
  o.x_label = "time (ms)";
  o.y_label = p.subject + " (cu)";
  o.title = p.subject + ", reference and candidate";
  d->Plot(SvgLinePlot({Line("reference", p.paired_time_s, p.reference_series),
                       Line("candidate", p.paired_time_s, p.candidate_series)},
                      o),
          o.title);
  // An oscillator's cycles overlap into a block at full length: show its first three periods.
  if (const auto& period = p.reference_metrics.period_s;
      period && p.reference_metrics.upward_crossings >= 4) {
    const double until = p.paired_time_s.front() + 3 * *period;
    o.title = p.subject + ", first three periods";
    d->Plot(SvgLinePlot({Line("reference", p.paired_time_s, p.reference_series, until),
                         Line("candidate", p.paired_time_s, p.candidate_series, until)},
                        o),
            o.title);
  }
  std::vector<double> difference;
  for (std::size_t i = 0; i < p.reference_series.size(); ++i)
    difference.push_back(p.candidate_series[i] - p.reference_series[i]);
  o.title = "candidate - reference, " + p.subject;
  o.y_label = "difference (cu)";
  d->Plot(SvgLinePlot({Line("candidate - reference", p.paired_time_s, difference)}, o), o.title);
}

void FitSection(const PipelineEvidence& e, Document* d) {
  d->Heading("5. Fit");
  if (!e.fit) {
    d->Paragraph("Not applicable: the scenario's manifest names no parameter to fit.");
    return;
  }
  d->Paragraph(e.fit->summary.BriefReport());
  d->Plot(ConvergencePlot(e.fit->summary), "loss per iteration (fit/history.json)");
}

void FramesSection(const PipelineEvidence& e, Document* d) {
  d->Heading("7. Frame check and parity gates");
  const compare::Gate* gate = e.parity.gate("frames");
  const double threshold = gate ? gate->threshold.value : 0.05;
  std::vector<std::vector<std::string>> rows = {{"frame", "time (ms)", "reference (cu)",
                                                 "candidate (cu)", "|delta| (of range)",
                                                 "threshold", "result"}};
  for (const auto& f : e.frames.value("frames", nlohmann::json::array())) {
    const double rel = f.value("relative_difference", 0.0);
    rows.push_back({std::to_string(f.value("reference_frame", std::size_t{0})),
                    FormatNumber(f.value("time_s", 0.0) * 1e3, 6),
                    FormatNumber(f.value("reference_value", 0.0), 6),
                    FormatNumber(f.value("candidate_value", 0.0), 6), FormatPercent(rel),
                    "< " + FormatPercent(threshold), rel < threshold ? "pass" : "FAIL"});
  }
  d->Table(rows);
  for (const auto& f : e.frames.value("frames", nlohmann::json::array()))
    d->Image("frames/" + f.value("image", std::string()), f.value("image", std::string()));
  const compare::ParityReport& p = e.parity;
  d->Paragraph("Parity of " + p.subject + ": " +
               (p.pass() ? "PASS" : "FAIL (failed: " + p.FailedGates() + ")") + "; " +
               std::to_string(p.paired_frames) + " paired frames from " +
               FormatNumber(p.common_window_start_s * 1e3, 6) + " ms to " +
               FormatNumber(p.common_window_end_s * 1e3, 6) + " ms; frame scale " +
               FormatNumber(p.scale, 6) + " cu (reference range), box scale " +
               FormatNumber(p.box_scale_cu, 6) + " cu.");
  std::vector<std::vector<std::string>> gates = {
      {"gate", "value", "threshold", "source", "result", "detail"}};
  for (const compare::Gate& g : p.gates)
    gates.push_back(
        {g.name, g.status == compare::GateStatus::kNotApplicable ? "-" : FormatNumber(g.value, 6),
         "< " + FormatNumber(g.threshold.value, 6) + " " + g.unit,
         compare::SourceName(g.threshold.source), compare::StatusName(g.status), g.detail});
  d->Table(gates);
}

}  // namespace

std::string ConvergencePlot(const sgd::FitSummary& summary) {
  Series loss{"loss L", {}, {}};
  for (const sgd::Iteration& it : summary.iterations) {
    loss.x.push_back(it.iteration);
    loss.y.push_back(it.loss);
  }
  PlotOptions o;
  o.title = "fit convergence";
  o.x_label = "iteration";
  o.y_label = "loss (log scale)";
  o.log_y = true;
  return SvgLinePlot({loss}, o);
}

Document PipelineIndex(const PipelineEvidence& e) {
  Document d("owval pipeline: " + e.scenario);
  d.Paragraph(e.description);
  d.Heading("Verdict");
  d.Paragraph(std::string("PR checklist: ") + ci::VerdictName(e.checklist.verdict) + ".");
  std::vector<std::vector<std::string>> phases = {{"phase", "applies", "outcome"}};
  for (const auto& p : e.phases)
    phases.push_back({p.name, p.applicable ? "yes" : "not applicable", p.summary});
  d.Table(phases);
  PredictionSection(e, &d);
  CandidateSection(e, &d);
  FitSection(e, &d);
  d.Heading("6. Side-by-side video");
  d.Video("sxs.mp4", "reference left, candidate right, one camera");
  FramesSection(e, &d);
  d.Heading("8. PR checklist");
  std::vector<std::vector<std::string>> items = {{"item", "result", "detail"}};
  for (const auto& i : e.checklist.items)
    items.push_back(
        {std::to_string(i.number) + ". " + i.title, i.pass ? "pass" : "FAIL", i.detail});
  items.push_back(
      {"parity gate", e.checklist.parity_pass() ? "pass" : "FAIL",
       e.checklist.parity ? e.checklist.parity->FailedGates() : e.checklist.parity_note});
  d.Table(items);
  return d;
}

std::string ChangesMarkdown(const PipelineEvidence& e) {
  std::string md = "# Substrate changes under test\n\n";
  md += "- Candidate substrate: " + e.candidate_source + ".\n";
  md += "- Reference substrate: " + e.reference_source + ".\n";
  md +=
      "- Constants: Sibernetic defaults (reference-equivalent); no [physical parameters] "
      "applied.\n";
  if (!e.fit) return md + "- Fit: not applicable for this scenario.\n";
  for (std::size_t i = 0; i < e.fit->parameters.size(); ++i) {
    const double final_value =
        i < e.fit->summary.final_values.size() ? e.fit->summary.final_values[i] : NAN;
    md += "- Fitted: " + e.fit->parameters[i].name + " from " +
          FormatNumber(e.fit->parameters[i].start, 6) + " to " + FormatNumber(final_value, 6) +
          " by " + sgd::SolverName(e.fit->solver) + " (history in fit/history.json).\n";
  }
  return md;
}

}  // namespace owval::reports
