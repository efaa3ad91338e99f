#pragma once
// Sibernetic's muscles_activity_buffer.txt: per logged iteration k (k % log_step == 0, k = 0
// included) one line of the 96 muscle activations, tab-separated, no iteration column, each the
// float printed as C++'s std::scientific at precision 6 prints it (printf's %e of the value as a
// double: 7 significant digits). Value i is muscle i+1's activation computed after iteration k
// and used by the elastic forces of iteration k+1 (Sibernetic's owPhysicsFluidSimulator::
// simulationStep asks main_sim.MuscleSimulation.run() for them, then logs them, then uploads them;
// ../shared/reference/README.md, "muscles_activity_buffer.txt").
// Like worm_motion_log.txt it is the producer's claim about its run: a port can write any numbers
// there. CompareMuscleLogWithSignal holds it to the signal computed for the trajectory's logged
// steps. Memory: one line, whatever the run's length.
#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "owval/base/atomic_output.hpp"
#include "owval/kinematics/side_files.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::kinematics {

constexpr std::size_t kLoggedMuscles = 96;

using MuscleActivations = std::array<float, kLoggedMuscles>;
using PrintedActivations = std::array<double, kLoggedMuscles>;  // as the file prints them

class LogLines;

// muscles_activity_buffer.txt[.gz] line by line (blank lines skipped). InputError naming the file
// and line on a line that is not 96 finite numbers, or longer than 1 MiB.
class MuscleLogReader {
 public:
  explicit MuscleLogReader(const std::filesystem::path& path);
  ~MuscleLogReader();
  MuscleLogReader(const MuscleLogReader&) = delete;
  MuscleLogReader& operator=(const MuscleLogReader&) = delete;

  // The next line's values; false at the end of the file.
  bool Next(PrintedActivations* values);
  std::size_t line_number() const;  // of the line Next returned last, from 1

 private:
  std::unique_ptr<LogLines> lines_;
  std::string line_;
};

// One line as Sibernetic writes it: 96 values printed %e, tab-separated, ending in '\n'.
std::string FormatMuscleLogLine(const MuscleActivations& activations);

// The file written a line per logged frame, atomically (Commit renames it into place).
class MuscleLogWriter {
 public:
  explicit MuscleLogWriter(const std::filesystem::path& path);
  void Append(const MuscleActivations& activations) {
    out_.stream() << FormatMuscleLogLine(activations);
  }
  void Commit() { out_.Commit(); }

 private:
  AtomicOutput out_;
};

// The activations a producer computed after iteration `step` (for owval: engine's
// MuscleSimulationSignal(step)).
using MuscleSignal = std::function<MuscleActivations(double step)>;

// The file's line j against signal(k), k the trajectory's frame j's step (its time over the time
// step, rounded), every value within %e's rounding (half a unit in its 7th significant digit)
// plus a float's (6e-8 of the value, for a producer printing its double); a zero must be zero.
// Line and frame counts must agree. A file of zeros only beside a
// trajectory that is not a worm agrees too: Sibernetic drives only configurations named "worm"
// and logs zeros for the others. Memory: one line; the trajectory's header only.
TrackAgreement CompareMuscleLogWithSignal(const std::filesystem::path& log,
                                          const Trajectory& trajectory, const MuscleSignal& signal);

}  // namespace owval::kinematics
