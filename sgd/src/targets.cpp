#include "owval/sgd/targets.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "owval/base/command_template.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/number_text.hpp"
#include "owval/compare/parity.hpp"
#include "owval/compare/signal_metrics.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval::sgd {
namespace fs = std::filesystem;
namespace {

// At least one part: "" is one empty part (parts.at(0) threw std::out_of_range, whose message
// "vector::_M_range_check: __n (which is 0) >= this->size()" reached the user).
std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  if (text.empty()) return {""};
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, separator);) parts.push_back(part);
  return parts;
}

// ParseDecimal's numbers: std::stod took "0x10", and " 1" with its leading space.
double Number(const std::string& text, const std::string& context) {
  if (const std::optional<double> v = ParseDecimal(text)) return *v;
  throw InputError(context + ": expected a number, found '" + text + "'");
}

std::pair<std::string, std::string> KeyValue(const std::string& text, const std::string& context) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(context + ": expected NAME=VALUE, found '" + text + "'");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

// A trajectory file's tracked series, read frame by frame.
TrackedSeries ReadSeries(const fs::path& file, const Track& track) {
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(file);
  return ReadTrackedSeries(*frames, track);
}

double Rms(const TrackedSeries& run, const TrackedSeries& reference,
           const std::string& reference_file) {
  const auto pairs = PairFramesByTime(reference, run);
  if (pairs.empty())
    throw InputError(reference_file, 0, "shares no frame time with the simulation");
  const std::vector<double>&ref = reference.value, &cand = run.value;
  double sum = 0;
  for (const auto& [fr, fc] : pairs) sum += (cand[fc] - ref[fr]) * (cand[fc] - ref[fr]);
  return std::sqrt(sum / double(pairs.size()));
}

double Measure(const compare::SignalMetrics& m, const std::string& metric) {
  // A signal without two crossings has no period: return a value far from any target so the
  // optimiser backs away instead of failing.
  if (metric == "period") return m.period_s ? *m.period_s : 1e3;
  if (metric == "half_amplitude") return m.half_amplitude ? *m.half_amplitude : 0;
  if (metric == "equilibrium") return m.equilibrium;
  throw InputError("unknown target metric '" + metric +
                   "': expected period, half_amplitude, equilibrium or rms");
}

}  // namespace

Target ParseTarget(const std::string& text) {
  const auto parts = Split(text, ':');
  Target t;
  std::string value;
  std::tie(t.metric, value) = KeyValue(parts.at(0), "--target " + text);
  t.value = Number(value, "--target " + text);
  std::set<std::string> given;
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const auto [key, v] = KeyValue(parts[i], "--target " + text);
    if (!given.insert(key).second)  // the last one won silently
      throw InputError("--target " + text + ": " + key + " is given twice");
    if (key == "scale")
      t.scale = Number(v, "--target scale");
    else if (key == "weight")
      t.weight = Number(v, "--target weight");
    else if (key == "ref")
      t.reference_file = v;
    else
      throw InputError("--target " + text + ": unknown option '" + key + "' (scale, weight, ref)");
  }
  if (!(t.scale > 0)) throw InputError("--target " + text + ": scale must be positive");
  // A negative weight made every residual NaN (its square root), refused only once the first
  // simulation had run.
  if (!(t.weight >= 0)) throw InputError("--target " + text + ": weight must be 0 or more");
  if (t.metric == "rms" && t.reference_file.empty())
    throw InputError("--target rms needs ref=FILE");
  if (t.metric != "period" && t.metric != "half_amplitude" && t.metric != "equilibrium" &&
      t.metric != "rms")  // refused before any simulation runs, not after the first
    throw InputError("--target " + text + ": unknown metric '" + t.metric +
                     "' (period, half_amplitude, equilibrium, rms)");
  // Only rms reads a reference: "period=1:ref=x" fitted the period to 1 and ignored x silently.
  if (t.metric != "rms" && given.count("ref"))
    throw InputError("--target " + text + ": ref applies only to rms targets, not " + t.metric);
  return t;
}

Parameter ParseParameter(const std::string& text) {
  const auto parts = Split(text, ':');
  Parameter p;
  std::string value;
  std::tie(p.name, value) = KeyValue(parts.at(0), "--param " + text);
  p.start = Number(value, "--param " + text);
  std::size_t i = 1;
  if (i < parts.size() && (parts[i] == "log" || parts[i] == "lin"))
    p.log_space = parts[i++] == "log";
  if (i + 2 == parts.size()) {
    p.lower = Number(parts[i], "--param " + text + ": lower bound");
    p.upper = Number(parts[i + 1], "--param " + text + ": upper bound");
  } else if (i != parts.size()) {
    throw InputError("--param " + text + ": expected NAME=START[:log|:lin][:LOWER:UPPER]");
  }
  if (p.log_space && !(p.start > 0))
    throw InputError("--param " + text + ": a log-space parameter must be positive");
  if (i + 2 == parts.size()) {  // bounds Ceres would reject after the first evaluations
    if (!(p.lower < p.upper)) throw InputError("--param " + text + ": expected LOWER < UPPER");
    if (p.start < p.lower || p.start > p.upper)
      throw InputError("--param " + text + ": expected LOWER <= START <= UPPER");
  }
  return p;
}

void LoadReferences(const Track& track, std::vector<Target>* targets) {
  for (Target& target : *targets)
    if (target.metric == "rms" && !target.reference)
      target.reference =
          std::make_shared<const TrackedSeries>(ReadSeries(target.reference_file, track));
}

std::vector<double> ScaledResiduals(const TrackedSeries& run, const Track& track,
                                    const std::vector<Target>& targets) {
  const compare::SignalMetrics m = compare::MeasureSignal(run.time_s, run.value);
  std::vector<double> r;
  for (const Target& target : targets) {
    double measured = 0;
    if (target.metric != "rms")
      measured = Measure(m, target.metric);
    else if (target.reference)
      measured = Rms(run, *target.reference, target.reference_file);
    else  // not loaded by LoadReferences: read for this call only
      measured = Rms(run, ReadSeries(target.reference_file, track), target.reference_file);
    r.push_back(std::sqrt(target.weight) * (measured - target.value) / target.scale);
  }
  return r;
}

nlohmann::json TargetsToJson(const std::vector<Target>& targets, const Track& k) {
  nlohmann::json j = nlohmann::json::array();
  for (const Target& t : targets)
    j.push_back({{"metric", t.metric},
                 {"value", t.value},
                 {"scale", t.scale},
                 {"weight", t.weight},
                 {"track", k.ToJson()}});
  return j;
}

Objective MakeObjective(Simulator simulator, Track tracking, std::vector<Target> targets) {
  LoadReferences(tracking, &targets);
  return [simulator = std::move(simulator), tracking, targets](const std::vector<double>& values) {
    return ScaledResiduals(simulator(values, tracking), tracking, targets);
  };
}

Simulator CommandSimulator(std::string command_template, std::vector<Parameter> parameters,
                           fs::path work_dir) {
  auto counter = std::make_shared<std::atomic<int>>(0);
  return [=](const std::vector<double>& values, const Track& track) {
    const fs::path out = work_dir / ("eval_" + std::to_string((*counter)++));
    fs::create_directories(out);
    const fs::path out_file = out / "trajectory.h5";
    TemplateValues placeholders;
    for (std::size_t i = 0; i < parameters.size(); ++i) {
      std::ostringstream v;
      v.precision(17);
      v << values[i];
      placeholders.values[parameters[i].name] = v.str();
    }
    placeholders.values["out_file"] = out_file.string();
    placeholders.values["out"] = out.string();
    // One pass, every value shell-quoted: a path holding "{out}" or a space stays one argument.
    const std::string command = ExpandTemplate(command_template, placeholders, true, "--command");
    const int status = std::system(
        (command + " > " + ShellQuote((out / "command.log").string()) + " 2>&1").c_str());
    if (status != 0)
      throw InputError(
          (out / "command.log").string(), 0,
          "external command failed (status " + std::to_string(status) + "): " + command);
    for (const fs::path& candidate : {out_file, out / "position_buffer.txt"})
      if (fs::exists(candidate)) return ReadSeries(candidate, track);
    throw InputError(
        out.string(), 0,
        "the command wrote no trajectory (expected trajectory.h5 or position_buffer.txt)");
  };
}

}  // namespace owval::sgd
