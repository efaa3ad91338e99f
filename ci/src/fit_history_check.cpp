// Item 6 of the checklist: the fit's convergence history (docs/checklist.md, item 6).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <sstream>

#include "checklist_evidence.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/json_file.hpp"
#include "owval/base/progress.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/constants.hpp"
#include "owval/sgd/fit_record.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/tracked_series.hpp"

namespace owval::ci::internal {
namespace fs = std::filesystem;
namespace {

// A number of a JSON object, or NaN when absent or not a number.
double NumberOr(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

// fit/history.json's string `key` of `j`, `fallback` when `j` is no object or lacks it;
// InputError naming the field when it is another type (json::value() threw nlohmann's "type must
// be string, but is number", which reached item 6's detail as it was).
std::string HistoryString(const nlohmann::json& j, const char* key, const std::string& where,
                          const std::string& fallback = "") {
  if (!j.is_object() || !j.contains(key)) return fallback;
  if (!j[key].is_string())
    throw InputError("fit/history.json", 0, where + key + ": expected a string");
  return j[key].get<std::string>();
}

std::string TargetMetric(const nlohmann::json& targets, std::size_t i,
                         const std::string& fallback = "") {
  return HistoryString(targets[i], "metric", "targets[" + std::to_string(i) + "].", fallback);
}

bool SameNumber(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max({1e-300, std::abs(a), std::abs(b)});
}

// history.json's claims against its own numbers (docs/fit_history.md): every iteration's loss is
// the sum of its squared residuals, final.loss is the best iteration's loss and converged says
// final.loss < loss_threshold. "converged": true written over a fit that did not converge (or a
// final loss copied from nowhere) was taken on trust. Returns the first contradiction, or "".
// Losses without residuals (gradient fits record none) cannot be recomputed: `unverified`
// counts them.
std::string HistoryContradiction(const nlohmann::json& h, std::size_t* unverified) {
  double best = INFINITY;
  for (const auto& it : h["iterations"]) {
    const double loss = NumberOr(it, "loss");
    if (!std::isfinite(loss)) return "an iteration has no finite loss";
    best = std::min(best, loss);
    const nlohmann::json none;
    const nlohmann::json& residuals =
        it.is_object() && it.contains("residuals") ? it["residuals"] : none;
    if (!residuals.is_array() || residuals.empty()) {
      ++*unverified;
      continue;
    }
    double sum = 0;
    for (const auto& r : residuals) sum += r.is_number() ? r.get<double>() * r.get<double>() : NAN;
    if (!SameNumber(sum, loss))
      return "iteration " + it.value("iteration", nlohmann::json()).dump() + " claims loss " +
             FormatNumber(loss, 6) + ", its residuals' sum of squares is " + FormatNumber(sum, 6);
  }
  const double final_loss = h.contains("final") ? NumberOr(h["final"], "loss") : NAN;
  if (!SameNumber(final_loss, best))
    return "final loss " + FormatNumber(final_loss, 6) + " is not the best iteration's, " +
           FormatNumber(best, 6);
  const double threshold = NumberOr(h, "loss_threshold");
  if (!(final_loss < threshold))
    return "converged is claimed, but the final loss " + FormatNumber(final_loss, 6) +
           " is not below loss_threshold " + FormatNumber(threshold, 6);
  return "";
}

// The history's targets against the caller's scenario's manifest ("fit.targets"): the same
// metrics in the same order with the same weights. "" when they agree or no scenario is named.
std::string TargetsAgainstScenario(const Evidence& e, const nlohmann::json& targets) {
  const nlohmann::json& expected = e.options.scenario_fit_targets;
  if (!expected.is_array()) return "";
  if (expected.size() != targets.size())
    return std::to_string(targets.size()) + " targets, the manifest names " +
           std::to_string(expected.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const std::string metric = expected[i].value("metric", std::string());
    const double weight = expected[i].value("weight", 1.0);
    if (TargetMetric(targets, i) != metric || !SameNumber(NumberOr(targets[i], "weight"), weight))
      return "target " + std::to_string(i + 1) + " is " + TargetMetric(targets, i, "?") +
             " weighted " + FormatNumber(NumberOr(targets[i], "weight"), 6) + ", the manifest's " +
             metric + " weighted " + FormatNumber(weight, 6);
  }
  return "";
}

// The targets' values against the directory's reference, measured as the pipeline's fit phase
// measures them (the tracked series' zero-crossing period, half-amplitude, equilibrium): a
// history whose targets were moved to what its parameters produce fails here. rms targets
// must aim at 0 (the reference itself) with a positive weight. Returns the first disagreement,
// or why the targets cannot be checked ("not verified: ...").
std::string TargetsAgainstReference(Evidence& e, const nlohmann::json& targets,
                                    std::shared_ptr<const TrackedSeries>* reference_series) {
  if (!targets.is_array() || targets.empty()) return "not verified: the history lists no target";
  if (const std::string differs = TargetsAgainstScenario(e, targets); !differs.empty())
    return "targets are not the scenario's: " + differs;
  if (!e.reference)
    return "not verified: the directory's reference trajectory, which the targets are measured "
           "on, is missing or unreadable";
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const nlohmann::json& t = targets[i];
    if (!t.is_object() || !t.contains("track")) return "not verified: a target names no track";
    const Track track = Track::FromJson(t["track"], "fit/history.json targets");
    if (!*reference_series)
      *reference_series =
          std::make_shared<const TrackedSeries>(ReadTrackedSeries(*e.reference, track));
    const TrackedSeries& series = **reference_series;
    const std::string metric = TargetMetric(targets, i);
    const double value = NumberOr(t, "value");
    if (!(NumberOr(t, "weight") > 0))
      return "targets do not match the directory's reference: target " + metric +
             " has no positive weight";
    // The pipeline's scales (|value|; rms: the reference's range) at most: a larger one shrinks
    // the residuals, and a bad fit converges.
    const double scale = NumberOr(t, "scale");
    // Positive, as `owval fit --target` requires: a residual is divided by the scale, not its
    // square, so -1000 times the value's magnitude passed the bounds below and shrank it as much.
    if (!(scale > 0))
      return "target " + metric + "'s scale " + FormatNumber(scale, 6) + " is not positive";
    if (metric == "rms") {
      if (value != 0)
        return "targets do not match the directory's reference: target rms aims at " +
               FormatNumber(value, 6) + ", not 0";
      const auto [lo, hi] = std::minmax_element(series.value.begin(), series.value.end());
      const double range = series.value.empty() ? 0 : *hi - *lo;
      if (!(scale <= std::max(range, 1e-300) * (1 + 1e-9)))
        return "target rms's scale " + FormatNumber(scale, 6) +
               " is looser than the reference's range " + FormatNumber(range, 6);
      continue;
    }
    const compare::SignalMetrics m = compare::MeasureSignal(series.time_s, series.value);
    const std::optional<double> measured = metric == "period"           ? m.period_s
                                           : metric == "half_amplitude" ? m.half_amplitude
                                           : metric == "equilibrium" ? std::optional(m.equilibrium)
                                                                     : std::nullopt;
    if (!measured) return "not verified: target " + metric + " cannot be measured on the reference";
    // 1e-4 relative: a target typed to 5 significant digits is the reference's; what moving it
    // that far can change is 1e-4 of a residual that converging allows up to 1e-2 of.
    if (!(std::abs(value - *measured) <= 1e-4 * std::abs(*measured)))
      return "targets do not match the directory's reference: target " + metric + " is " +
             FormatNumber(value, 6) + ", the reference's " + track.Describe() + " measures " +
             FormatNumber(*measured, 6);
    if (!(scale <= std::max(std::abs(value), 1e-12) * (1 + 1e-9)))
      return "target " + metric + "'s scale " + FormatNumber(scale, 6) +
             " is looser than its value's magnitude";
  }
  return "";
}

bool SameConfiguration(const engine::SiberneticConfig& a, const engine::SiberneticConfig& b) {
  return a.position == b.position && a.velocity == b.velocity && a.connection == b.connection &&
         a.membranes == b.membranes && a.particle_mem_index == b.particle_mem_index &&
         std::memcmp(&a.box, &b.box, sizeof a.box) == 0;
}

// The fit's configuration against the caller's scenario's and the directory's
// (configuration.txt, when it holds one): the box, particles, velocities, connections and
// membranes must be the same numbers. A missing fit/configuration.txt is left to the rerun.
std::string ConfigurationAgainstExpected(const Evidence& e) {
  const fs::path fitted = e.dir / "fit" / "configuration.txt", mine = e.dir / "configuration.txt";
  if (!fs::is_regular_file(fitted)) return "";
  const engine::SiberneticConfig fit = engine::ReadSiberneticConfig(fitted);
  if (e.options.scenario_configuration &&
      !SameConfiguration(fit, *e.options.scenario_configuration))
    return "the fit's configuration.txt is not the scenario's configuration";
  if (fs::is_regular_file(mine) && !SameConfiguration(fit, engine::ReadSiberneticConfig(mine)))
    return "the fit's configuration.txt is not the directory's configuration.txt";
  return "";
}

// Residuals that agree within the caller's relative tolerance (absolute 1e-12 near 0). The
// engine is deterministic on one thread and the rerun goes through the fit's own simulator and
// loss, so its numbers are the same to the last bit and the default 1e-9 only absorbs a decimal
// rendering of the history, which JSON's shortest round-trip form does not even need; a port on
// another substrate need not reproduce its own runs to the last bit (--fit-rerun-tolerance).
bool SameResiduals(const nlohmann::json& recorded, const std::vector<double>& rerun,
                   double relative_tolerance) {
  if (!recorded.is_array() || recorded.size() != rerun.size()) return false;
  for (std::size_t i = 0; i < rerun.size(); ++i) {
    const double a = recorded[i].is_number() ? recorded[i].get<double>() : NAN;
    if (!(std::abs(a - rerun[i]) <=
          std::max(1e-12, relative_tolerance * std::max(std::abs(a), std::abs(rerun[i])))))
      return false;
  }
  return true;
}

bool SameLoss(double rerun, double claimed, double relative_tolerance) {
  return std::abs(rerun - claimed) <=
         relative_tolerance * std::max({1e-300, std::abs(rerun), std::abs(claimed)});
}

bool IsModelFit(const nlohmann::json& h) {
  return h.contains("simulation") && h["simulation"].is_object() &&
         HistoryString(h["simulation"], "kind", "simulation.") == "xpbd_model";
}

// A gradient fit's loss compares the model with a trajectory: it must be the directory's
// reference file, byte for byte (its recorded FNV-1a 64), else a fit against a trajectory of
// the forger's making would rerun as recorded.
std::string LossReferenceAgainstDirectory(const Evidence& e, const nlohmann::json& h) {
  const fs::path& mine = e.reference_file;
  if (mine.empty())
    return "not verified: the directory holds no reference to hold the fit's loss reference to";
  const nlohmann::json none;
  const nlohmann::json& loss = h["simulation"].contains("loss") ? h["simulation"]["loss"] : none;
  const nlohmann::json& recorded =
      loss.is_object() && loss.contains("reference") ? loss["reference"] : none;
  if (!recorded.is_object() ||
      HistoryString(recorded, "fnv1a64", "simulation.loss.reference.") != sgd::FileFnv1a64Hex(mine))
    return "the fit's loss reference is not the directory's " + mine.filename().string();
  if (!e.reference)
    return "not verified: the directory's " + mine.filename().string() + " cannot be read";
  return "";
}

// The targets (a gradient fit's loss) are measured on the directory's reference, so the fit
// simulates at most its time span (and one frame interval of rounding): a history claiming a
// longer run is another fit, and rerunning it would take as long as the history says. "" when
// `duration_s` is within it or not a number (the rerun says so).
std::string LongerThanReference(const Evidence& e, double duration_s) {
  const std::vector<double>& t = e.reference->header().time_s;
  const double span = t.empty() ? 0 : t.back(),
               frame = t.size() > 1 ? (t.back() - t.front()) / double(t.size() - 1) : 0;
  if (!(duration_s > span + frame)) return "";
  return "not verified: the fit simulated " + FormatNumber(duration_s, 6) +
         " s, longer than the directory's reference (" + FormatNumber(span, 6) + " s)";
}

// A gradient fit's run: its steps at the model's time step (the default constants', as
// DifferentiableXpbd is built by the fit and the rerun).
std::string ModelStepsAgainstReference(const Evidence& e, const nlohmann::json& simulation) {
  const double steps = NumberOr(simulation, "steps");
  const std::string longer = LongerThanReference(e, steps * engine::PhysicsConstants{}.time_step_s);
  if (longer.empty()) return "";
  return longer + " (" + FormatNumber(steps, 6) + " steps of " +
         FormatNumber(engine::PhysicsConstants{}.time_step_s, 6) + " s)";
}

// A gradient fit's loss scale at most the scale the checklist's own frame gates measure the same
// quantity by (docs/checklist.md, item 6): the tracked coordinate's range over the reference
// (`frames`: "of the reference range"), or, for group centroids, the box's largest side
// (`frames.group_centroids`: "of the box"). A larger scale shrinks every residual, and a bad
// fit converges.
std::string LossScaleAgainstReference(Evidence& e, const nlohmann::json& loss) {
  const double scale = NumberOr(loss, "scale");
  const bool groups =
      loss.contains("groups") && loss["groups"].is_array() && !loss["groups"].empty();
  double bound = 0;
  std::string what;
  if (groups) {
    const Box& box = e.reference->header().box;
    bound = std::max({box.extent(0), box.extent(1), box.extent(2)});
    what = "the reference's box's largest side";
  } else {
    if (!loss.contains("track")) return "not verified: the fit's loss names no track";
    const Track track = Track::FromJson(loss["track"], "fit/history.json simulation.loss");
    const TrackedSeries series = ReadTrackedSeries(*e.reference, track);
    const auto [lo, hi] = std::minmax_element(series.value.begin(), series.value.end());
    bound = series.value.empty() ? 0 : *hi - *lo;
    what = "the reference's " + track.Describe() + " range";
  }
  // |scale|: the loss divides by its square, so -1000 shrinks it as 1000 does.
  if (std::abs(scale) <= std::max(bound, 1e-300) * (1 + 1e-9)) return "";
  return "the loss's scale " + FormatNumber(scale, 6) + " cu is looser than " + what + " (" +
         FormatNumber(bound, 6) + " cu)";
}

// The gradient fit's record against the directory: its loss reference is the directory's, its
// run no longer than that reference, its loss scale no looser than the frame gates'.
std::string ModelFitAgainstReference(Evidence& e, const nlohmann::json& h) {
  if (const std::string other = LossReferenceAgainstDirectory(e, h); !other.empty()) return other;
  const nlohmann::json& simulation = h["simulation"];
  if (const std::string longer = ModelStepsAgainstReference(e, simulation); !longer.empty())
    return longer;
  if (!simulation.contains("loss") || !simulation["loss"].is_object())
    return "not verified: the fit's simulation records no loss";
  return LossScaleAgainstReference(e, simulation["loss"]);
}

// The rerun's best loss judged with no target weighted below 1 (docs/checklist.md, item 6):
// Σ r_i² / min(w_i, 1) over the rerun's residuals, one per target. A weight only the history
// names (1e-6) shrank its residual a thousandfold and a bad fit converged; a weight above 1
// only makes the judgement stricter. NaN when the residuals are not one per target;
// `raised` names the targets weighted below 1.
double LossWithWeightsOfAtLeastOne(const nlohmann::json& targets,
                                   const std::vector<double>& residuals, std::string* raised) {
  if (!targets.is_array() || targets.size() != residuals.size()) return NAN;
  double loss = 0;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    const double weight = NumberOr(targets[i], "weight");
    loss += residuals[i] * residuals[i] / std::min(weight, 1.0);
    if (weight < 1)
      *raised += std::string(raised->empty() ? "" : ", ") + TargetMetric(targets, i, "?") +
                 " weighted " + FormatNumber(weight, 6);
  }
  return loss;
}

// Why the history's record cannot be rerun as the directory's evidence ("" when it can). Runs
// scored by targets (the engine's, or a named backend's): the targets, run length and weights are
// held to the directory's reference (`reference` receives the targets' tracked series); a model
// fit to its own record; every fit's configuration to the expected one.
std::string RecordDisagreement(Evidence& e, const nlohmann::json& h, bool engine_fit,
                               const nlohmann::json& targets,
                               std::shared_ptr<const TrackedSeries>* reference) {
  if (engine_fit) {
    const std::string moved = TargetsAgainstReference(e, targets, reference);
    if (!moved.empty()) return moved;
    const std::string longer = LongerThanReference(e, NumberOr(h["simulation"], "duration_s"));
    if (!longer.empty()) return longer;
  } else if (IsModelFit(h)) {
    if (const std::string other = ModelFitAgainstReference(e, h); !other.empty()) return other;
  }
  return ConfigurationAgainstExpected(e);
}

// The history's best iterate rerun with its recorded simulation (through the caller's backend
// entry when one is named), its progress shown on the terminal.
sgd::FitRerun RerunBest(Evidence& e, const nlohmann::json& h,
                        const std::shared_ptr<const TrackedSeries>& reference) {
  Progress progress("checklist: rerunning the fit's best parameters", 0, QuietMode());
  sgd::FitRerunOptions options;
  options.rms_reference = reference;
  options.loss_reference = e.reference.get();  // held to the record's hash by RecordDisagreement
  if (e.options.fit_backend) options.backend = &*e.options.fit_backend;  // the caller's entry
  options.on_step = [&](std::size_t done, std::size_t total) {
    progress.Update(done, std::to_string(done) + "/" + std::to_string(total) + " steps");
  };
  sgd::FitRerun rerun = sgd::RerunBestIterate(h, e.dir / "fit", options);
  progress.Finish();
  return rerun;
}

// Whether the rerun reproduces the best iteration's loss and residuals within the caller's
// tolerance ("" when it does, else why not). `rerun_detail` receives the rerun's loss against the
// history's, and e.rerun_at_default_tolerance whether it reproduces at DD001's tolerance too.
std::string ReproductionDisagreement(Evidence& e, const sgd::FitRerun& rerun,
                                     std::string* rerun_detail) {
  const nlohmann::json& best = rerun.best_iteration;
  const double claimed = NumberOr(best, "loss");
  const double tolerance = e.options.fit_rerun_tolerance;
  *rerun_detail = "rerun at the best parameters (" + rerun.simulated + "): loss " +
                  FormatNumber(rerun.loss, 6) + ", history says " + FormatNumber(claimed, 6) +
                  " (tolerance " + FormatNumber(tolerance, 3) + " relative)";
  const nlohmann::json& recorded =
      best.contains("residuals") ? best["residuals"] : nlohmann::json();
  const auto reproduces = [&](double relative_tolerance) {
    return SameLoss(rerun.loss, claimed, relative_tolerance) &&
           SameResiduals(recorded, rerun.residuals, relative_tolerance);
  };
  e.rerun_at_default_tolerance = reproduces(ChecklistOptions{}.fit_rerun_tolerance)
                                     ? "the rerun reproduces the best iteration at the default too"
                                     : "at the default the rerun does NOT reproduce the best "
                                       "iteration's residuals";
  if (!reproduces(tolerance)) return "the rerun does not reproduce the best iteration's residuals";
  return "";
}

// The rerun's own loss against the caller's threshold ("" when below, else why not): the
// tolerance is the caller's to loosen, never a way for a claimed loss the rerun does not reach to
// pass. A fit scored by targets is judged with no target weight below 1 (noted in rerun_detail).
std::string RerunLossDisagreement(const Evidence& e, bool engine_fit, const nlohmann::json& targets,
                                  const sgd::FitRerun& rerun, std::string* rerun_detail) {
  if (!engine_fit) {
    if (rerun.loss < e.options.fit_loss_threshold) return "";
    return "the rerun's loss " + FormatNumber(rerun.loss, 6) +
           " is not below the caller's threshold " + FormatNumber(e.options.fit_loss_threshold, 6);
  }
  std::string raised;
  const double judged = LossWithWeightsOfAtLeastOne(targets, rerun.residuals, &raised);
  *rerun_detail += "; with no weight below 1" +
                   (raised.empty() ? "" : " (" + raised + " raised to 1)") + ", loss " +
                   FormatNumber(judged, 6);
  if (judged < e.options.fit_loss_threshold) return "";
  return "the best loss with no weight below 1 is " + FormatNumber(judged, 6) +
         ", not below the caller's threshold " + FormatNumber(e.options.fit_loss_threshold, 6);
}

// The history's best iterate rerun once with its recorded simulation; "" when the rerun's
// residuals and loss are the history's, else why not (docs/checklist.md, item 6).
std::string RerunDisagreement(Evidence& e, const nlohmann::json& h, std::string* rerun_detail) {
  const nlohmann::json& targets = h.contains("targets") ? h["targets"] : nlohmann::json();
  std::shared_ptr<const TrackedSeries> reference;
  const std::string kind =
      h.contains("simulation") ? HistoryString(h["simulation"], "kind", "simulation.") : "";
  const bool engine_fit = kind == "engine" || kind == "backend";
  const std::string unfit = RecordDisagreement(e, h, engine_fit, targets, &reference);
  if (!unfit.empty()) return unfit;
  const sgd::FitRerun rerun = RerunBest(e, h, reference);
  if (!rerun.not_verified.empty()) return "not verified: " + rerun.not_verified;
  const std::string unreproduced = ReproductionDisagreement(e, rerun, rerun_detail);
  if (!unreproduced.empty()) return unreproduced;
  return RerunLossDisagreement(e, engine_fit, targets, rerun, rerun_detail);
}

// fit/history.json of the directory: an object whose "converged", when present, is a boolean.
nlohmann::json ReadFitHistory(const fs::path& dir) {
  nlohmann::json h = ReadJsonFile(dir / "fit" / "history.json");
  if (!h.is_object())
    throw InputError((dir / "fit/history.json").string(), 0, "expected an object");
  if (h.contains("converged") && !h["converged"].is_boolean())
    throw InputError((dir / "fit/history.json").string(), 0, "converged: expected true or false");
  return h;
}

}  // namespace

// ReadFitHistory of the evidence's directory, read by the first item that asks (item 6, whose
// verdict item 8 holds the tuned values to): both judge the same file's contents.
const nlohmann::json& FitHistory(Evidence& e) {
  if (!e.fit_history && !e.fit_history_unreadable) {
    try {
      e.fit_history = ReadFitHistory(e.dir);
    } catch (...) {
      e.fit_history_unreadable = std::current_exception();
    }
  }
  if (e.fit_history_unreadable) std::rethrow_exception(e.fit_history_unreadable);
  return *e.fit_history;
}

namespace {

// "N iterations, stop reason: R[, final loss L]", as the history states them.
std::string HistoryDescription(const nlohmann::json& h, std::size_t iterations) {
  std::ostringstream s;
  s << iterations << " iterations, stop reason: "
    << (h.contains("stop_reason") && h["stop_reason"].is_string()
            ? h["stop_reason"].get<std::string>()
            : "?");
  if (h.contains("final") && h["final"].is_object() && h["final"].contains("loss") &&
      h["final"]["loss"].is_number())
    s << ", final loss " << h["final"]["loss"].get<double>();
  return s.str();
}

// What a converged history's own numbers fail to support, as the detail's next clause ("" when
// they support it): losses its residuals contradict, iterations with no residuals to recompute
// from, or a best loss not below the caller's threshold.
std::string UnsupportedConvergence(const Evidence& e, const nlohmann::json& h) {
  std::size_t unverified = 0;
  const std::string contradiction = HistoryContradiction(h, &unverified);
  if (!contradiction.empty()) return "; CONTRADICTED by its own numbers: " + contradiction;
  if (unverified > 0) {
    // Nothing in the file to recompute those losses from: a claim, not evidence.
    return "; converged claimed, not verified: " + std::to_string(unverified) +
           " iteration(s) record no residuals to recompute the loss from";
  }
  const double best = NumberOr(h["final"], "loss");
  if (!(best < e.options.fit_loss_threshold)) {
    return "; FAILS: the best loss " + FormatNumber(best, 6) +
           " is not below the caller's threshold " + FormatNumber(e.options.fit_loss_threshold, 6) +
           " (the history's own loss_threshold is " +
           FormatNumber(NumberOr(h, "loss_threshold"), 6) + ")";
  }
  return "";
}

}  // namespace

// The rerun's verdict on the best iterate, appended to the item's detail; the item passes only
// when the rerun agrees.
void JudgeRerun(Evidence& e, const nlohmann::json& h, ChecklistItem* item) {
  std::string rerun;
  const std::string disagreement = RerunDisagreement(e, h, &rerun);
  if (!rerun.empty()) item->detail += "; " + rerun;
  if (!disagreement.empty()) {
    item->detail += "; " + (disagreement.rfind("not verified", 0) == 0 ? disagreement
                                                                       : "FAILS: " + disagreement);
    return;
  }
  item->pass = true;
  item->detail +=
      "; each loss, the best one and converged agree with the residuals, and the rerun "
      "reproduces the best iteration's residuals";
}

void CheckFitHistory(Evidence& e, ChecklistItem* item) {
  const nlohmann::json& h = FitHistory(e);
  const bool converged = h.value("converged", false);
  const std::size_t iterations =
      h.contains("iterations") && h["iterations"].is_array() ? h["iterations"].size() : 0;
  item->detail = HistoryDescription(h, iterations);
  item->pass = converged && iterations > 0;
  if (!converged) item->detail += " (not converged)";
  if (!item->pass) return;
  const std::string unsupported = UnsupportedConvergence(e, h);
  item->pass = false;
  if (!unsupported.empty()) {
    item->detail += unsupported;
    return;
  }
  JudgeRerun(e, h, item);
}

}  // namespace owval::ci::internal
