#include "owval/kinematics/muscle_log.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "log_lines.hpp"
#include "owval/base/errors.hpp"
#include "owval/kinematics/midline.hpp"

namespace owval::kinematics {
namespace {

constexpr const char* kExpected = "96 finite muscle activations, tab-separated (%e)";

// How far a printed value may be from `expected`: %e's rounding, half a unit in the 7th
// significant digit (5e-7 of the decimal exponent's power of ten), plus a float's rounding (6e-8
// of the value: a producer printing the double it computed rather than Sibernetic's float). A
// value whose 7th digit moved by two units is outside it; zero must print zero.
double Allowance(double expected) {
  if (expected == 0) return 0;
  const double magnitude = std::abs(expected);
  return 5e-7 * std::pow(10.0, std::floor(std::log10(magnitude))) + 6e-8 * magnitude;
}

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// One line's values into `values`; false for a blank line. InputError naming the file and line
// on anything but 96 finite numbers separated by blanks. from_chars: no locale, and no reading
// past the line (a line may hold a NUL byte).
bool ParseLine(const std::string& line, const LogLines& lines, PrintedActivations* values) {
  const char* at = line.data();
  const char* const end = line.data() + line.size();
  const auto skip = [&] {
    while (at != end && IsSpace(*at)) ++at;
  };
  skip();
  if (at == end) return false;
  for (std::size_t i = 0; i < kLoggedMuscles; ++i) {
    skip();
    if (at == end)
      throw InputError(lines.path().string(), lines.number(),
                       std::to_string(i) + " values; expected " + kExpected);
    double value = 0;
    const auto [next, error] = std::from_chars(at, end, value);
    if (error != std::errc() || !std::isfinite(value) || (next != end && !IsSpace(*next)))
      throw InputError(
          lines.path().string(), lines.number(),
          "value " + std::to_string(i + 1) + " is not a finite number; expected " + kExpected);
    (*values)[i] = value;
    at = next;
  }
  skip();
  if (at != end)
    throw InputError(lines.path().string(), lines.number(),
                     std::string("more than 96 values; expected ") + kExpected);
  return true;
}

std::string Format(const char* format, double a, double b = 0) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

}  // namespace

MuscleLogReader::MuscleLogReader(const std::filesystem::path& path)
    : lines_(std::make_unique<LogLines>(path, kExpected)) {}

MuscleLogReader::~MuscleLogReader() = default;

bool MuscleLogReader::Next(PrintedActivations* values) {
  while (lines_->Next(&line_))
    if (ParseLine(line_, *lines_, values)) return true;
  return false;
}

std::size_t MuscleLogReader::line_number() const { return lines_->number(); }

std::string FormatMuscleLogLine(const MuscleActivations& activations) {
  std::string line;
  char value[32];
  for (std::size_t i = 0; i < kLoggedMuscles; ++i) {
    std::snprintf(value, sizeof value, "%e", static_cast<double>(activations[i]));
    line += value;
    line += i + 1 == kLoggedMuscles ? '\n' : '\t';
  }
  return line;
}

MuscleLogWriter::MuscleLogWriter(const std::filesystem::path& path) : out_(path) {
  out_.stream();  // an empty run still writes an (empty) file
}

namespace {

// The file's lines against the signal at the frames' steps, a line at a time.
class SignalCheck {
 public:
  SignalCheck(const Trajectory& trajectory, const MuscleSignal& signal)
      : traj_(trajectory), signal_(signal) {}

  void Add(const PrintedActivations& got) {
    const std::size_t j = lines_++;
    for (double v : got) all_zero_ = all_zero_ && v == 0;
    if (j >= traj_.time_s.size()) return;  // counted, not compared
    const double step = std::round(traj_.time_s[j] / traj_.time_step_s);
    const MuscleActivations expected = signal_(step);
    bool failing = false;
    for (std::size_t m = 0; m < kLoggedMuscles; ++m) {
      const double e = expected[m];
      const double allowance = Allowance(e);
      const double difference = std::abs(got[m] - e);
      const double fraction = difference == 0  ? 0
                              : allowance == 0 ? INFINITY
                                               : difference / allowance;
      failing = failing || !(fraction <= 1);
      if (fraction > worst_) {
        worst_ = fraction;
        worst_where_ = " at line " + std::to_string(j + 1) + Format(" (step %.0f), muscle ", step) +
                       std::to_string(m + 1) + Format(": %.7g, the signal %.9g", got[m], e);
      }
    }
    failing_ += failing;
  }

  TrackAgreement Result() const {
    TrackAgreement a;
    const std::size_t frames = traj_.time_s.size();
    if (lines_ != frames) {
      a.worst_fraction_of_allowance = INFINITY;
      a.detail =
          std::to_string(lines_) + " lines, the trajectory " + std::to_string(frames) + " frames";
      return a;
    }
    if (failing_ > 0 && all_zero_ && !IsWorm(traj_)) {
      a.agrees = true;
      a.detail = std::to_string(lines_) +
                 " lines, all zero: no muscle signal, as Sibernetic logs for a configuration not "
                 "named a worm";
      return a;
    }
    a.agrees = failing_ == 0;
    a.worst_fraction_of_allowance = worst_;
    a.detail = std::to_string(lines_) + " lines; " + std::to_string(failing_) +
               " disagree with owval's muscle signal at their steps" +
               Format("; worst %.3g of its allowance", worst_) + worst_where_;
    return a;
  }

 private:
  const Trajectory& traj_;
  const MuscleSignal& signal_;
  std::size_t lines_ = 0, failing_ = 0;
  bool all_zero_ = true;
  double worst_ = 0;
  std::string worst_where_;
};

}  // namespace

TrackAgreement CompareMuscleLogWithSignal(const std::filesystem::path& log,
                                          const Trajectory& trajectory,
                                          const MuscleSignal& signal) {
  if (!(trajectory.time_step_s > 0))
    throw InputError("the trajectory records no time step: its frames' steps are unknown");
  MuscleLogReader reader(log);
  SignalCheck check(trajectory, signal);
  PrintedActivations values{};
  while (reader.Next(&values)) check.Add(values);
  return check.Result();
}

}  // namespace owval::kinematics
