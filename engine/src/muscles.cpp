#include "owval/engine/muscles.hpp"

#include <cmath>
#include <filesystem>

#include "owval/base/errors.hpp"
#include "owval/base/one_line.hpp"

namespace owval::engine {
namespace {

constexpr double kPi = 3.14159265358979323846;  // math.pi
constexpr int kRows = 12;                       // muscle rows per wave (24 muscles / 2)

// numpy.linspace(start, stop, 12)[i]: i·step + start, the last point exactly stop.
double Linspace(double start, double stop, int i) {
  if (i == kRows - 1) return stop;
  const double step = (stop - start) / double(kRows - 1);
  return double(i) * step + start;
}

struct Waves {
  double wave[2][kRows];
};

// main_sim.parallel_waves(step=n), in the order and precision Python evaluates it.
Waves ParallelWaves(double n) {
  const bool crawling = n > 1200000;
  const double velocity = crawling ? 4 * 0.000015 * 0.72 : 4 * 0.000015 * 3.7;
  const double coefficient = crawling ? 1.0 : 0.575;
  static constexpr double kSwimmingWeights[kRows] = {0.81, 0.90, 0.97, 1.00, 0.99, 0.95,
                                                     0.88, 0.78, 0.65, 0.53, 0.40, 0.25};
  Waves w{};
  for (int r = 0; r < kRows; ++r) {
    const double position = crawling ? Linspace(0, 2.97 * kPi, r) : Linspace(0, 0.81 * kPi, r);
    const double weight = crawling ? Linspace(1, 0.6, r) : kSwimmingWeights[r];
    const double phase = position - velocity * n;
    const double sines[2] = {std::sin(phase), std::sin(phase + kPi)};
    for (int k = 0; k < 2; ++k) {
      const double rectified = sines[k] > 0 ? sines[k] : 0.0;  // abs(x·(x > 0))
      double value = coefficient * rectified * weight;
      if (n < 10000 / 4) value = value * n / (10000 / 4);  // smooth start
      w.wave[k][r] = value;
    }
  }
  return w;
}

}  // namespace

std::array<float, kMuscleCount> MuscleSimulationSignal(double n) {
  const Waves w = ParallelWaves(n);
  // run() returns concatenate([wave 1, wave 2, wave 2, wave 1]), each row value twice.
  static constexpr int kBlockWave[4] = {0, 1, 1, 0};
  std::array<float, kMuscleCount> signal{};
  for (int m = 0; m < kMuscleCount; ++m)
    signal[m] = float(w.wave[kBlockWave[m / 24]][(m % 24) / 2]);
  return signal;
}

bool NamesAWorm(const std::string& configuration_path) {
  const std::filesystem::path p(configuration_path);
  const std::string name = p.filename().string();
  if (name.find("worm") != std::string::npos) return true;
  return name == "configuration" &&
         p.parent_path().filename().string().find("worm") != std::string::npos;
}

bool DrivesMuscles(MuscleSignal signal, const std::string& configuration_path) {
  return signal == MuscleSignal::kSwimmingWaves ||
         (signal == MuscleSignal::kAuto && NamesAWorm(configuration_path));
}

MuscleSignal ParseMuscleSignal(const std::string& name) {
  if (name == "auto") return MuscleSignal::kAuto;
  if (name == "off") return MuscleSignal::kOff;
  if (name == "waves") return MuscleSignal::kSwimmingWaves;
  throw InputError("muscles: expected auto, off or waves, found '" + OneLine(name, 40) + "'");
}

const char* MuscleSignalName(MuscleSignal signal) {
  return signal == MuscleSignal::kOff             ? "off"
         : signal == MuscleSignal::kSwimmingWaves ? "waves"
                                                  : "auto";
}

}  // namespace owval::engine
