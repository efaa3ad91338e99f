// owval inspect TRAJ: phase-3 measurements of one coordinate of a particle or group centroid.
#include <cstdio>
#include <iostream>

#include "command.hpp"
#include "owval/base/errors.hpp"
#include "owval/compare/metrics_json.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/trajectory/formats.hpp"
#include "resolve.hpp"

namespace owval::cli {
namespace {

struct InspectArgs {
  std::string path;
  long particle = -1;
  std::string group;
  std::string axis = "y";
  double start_s = -1, end_s = -1;
  std::string layout = "auto";
  bool json = false;
};

std::string Ms(const std::optional<double>& s) {
  char b[64];
  if (!s) return "n/a";
  std::snprintf(b, sizeof b, "%.6g ms", *s * 1e3);
  return b;
}
std::string Cu(const std::optional<double>& v, const char* unit = "cu") {
  char b[64];
  if (!v) return "n/a";
  std::snprintf(b, sizeof b, "%.6g %s", *v, unit);
  return b;
}

void PrintTable(const compare::SignalMetrics& m, const std::string& subject,
                const TextReadReport& read) {
  std::printf("%s\n", read.description.c_str());
  std::printf("signal: %s, %zu samples, t = %.6g .. %.6g s\n\n", subject.c_str(), m.samples,
              m.window_start_s, m.window_end_s);
  std::printf("%-26s %s\n", "zero-crossing period", Ms(m.period_s).c_str());
  std::printf("%-26s %zu upward, spread %s\n", "  crossings", m.upward_crossings,
              Ms(m.period_spread_s).c_str());
  std::printf("%-26s %s%s\n", "half-amplitude", Cu(m.half_amplitude).c_str(),
              m.whole_cycles ? "" : " (no whole cycle: half the range)");
  std::printf("%-26s %.6g cu%s\n", "equilibrium", m.equilibrium,
              m.whole_cycles ? "" : " (window mean)");
  std::printf("%-26s %s\n", "drift", Cu(m.drift_per_s, "cu/s").c_str());
  std::printf("%-26s %s\n", "logarithmic decrement", Cu(m.log_decrement, "").c_str());
  std::printf("%-26s %s\n", "settling time (2% band)", Ms(m.settling_time_s).c_str());
  std::printf("%-26s initial %.6g, final %.6g cu\n", "values", m.initial_value, m.final_value);
  std::printf("%-26s %.6g cu at %.6g ms .. %.6g cu at %.6g ms\n", "range (min .. max)", m.minimum,
              m.time_of_minimum_s * 1e3, m.maximum, m.time_of_maximum_s * 1e3);
}

void RunInspect(const InspectArgs& a) {
  TextReadReport read;
  const Trajectory t = ReadTrajectoryArgument(a.path, a.layout, &read);
  const int axis = ParseAxis(a.axis);
  std::vector<double> series;
  std::string subject;
  if (!a.group.empty()) {
    series = CentroidSeries(t, GroupIndices(t, a.group), axis);
    subject = a.group + " centroid " + a.axis;
  } else {
    const std::size_t particle = a.particle < 0 ? 0 : static_cast<std::size_t>(a.particle);
    series = ParticleSeries(t, particle, axis);
    subject = "particle " + std::to_string(particle) + " " + a.axis;
  }
  const compare::SignalMetrics m = compare::MeasureSignal(t.time_s, series, {a.start_s, a.end_s});
  std::optional<kinematics::Report> worm;  // a worm also gets its kinematics (issue 15)
  if (kinematics::IsWorm(t)) worm = kinematics::Analyse(kinematics::SkeletonsFromTrajectory(t));
  if (a.json) {
    nlohmann::json out = {{"file", a.path},
                          {"layout", read.description},
                          {"signal", subject},
                          {"metrics", compare::ToJson(m)}};
    if (worm) out["kinematics"] = worm->ToJson();
    std::cout << out.dump(2) << "\n";
  } else {
    PrintTable(m, subject, read);
    if (worm) std::printf("\nworm kinematics: %s", worm->ToText().c_str());
  }
}

void SetUp(CLI::App& app) {
  auto args = std::make_shared<InspectArgs>();
  CLI::App* cmd = app.add_subcommand(
      "inspect", "Phase 3: period, amplitude, equilibrium, drift, damping, settling");
  cmd->add_option("trajectory", args->path, "Trajectory file (position_buffer.txt or .h5)")
      ->required();
  auto* particle =
      cmd->add_option("--particle", args->particle, "Particle index (file order; default 0)");
  cmd->add_option("--group", args->group, "Group centroid instead: elastic, liquid or all")
      ->excludes(particle)
      ->check(CLI::IsMember({"elastic", "liquid", "all"}));
  cmd->add_option("--axis", args->axis, "x, y or z")->check(CLI::IsMember({"x", "y", "z"}));
  cmd->add_option("--from", args->start_s, "Window start (s)");
  cmd->add_option("--to", args->end_s, "Window end (s)");
  cmd->add_option("--layout", args->layout, "Text layout: auto, opencl or native")
      ->check(CLI::IsMember({"auto", "opencl", "native"}));
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args] { RunInspect(*args); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
