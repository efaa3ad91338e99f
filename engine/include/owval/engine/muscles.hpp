#pragma once
// Muscle activation signals. Sibernetic drives the muscles of a configuration whose file name
// contains "worm" with its Python module main_sim.MuscleSimulation: 96 activations per step from
// two rectified travelling sine waves (physics sheet §4). owval computes the same values in
// closed form, with the same double arithmetic, so a worm run needs no Python.
#include <array>
#include <cstddef>
#include <string>

namespace owval::engine {

constexpr int kMuscleCount = 96;

enum class MuscleSignal {
  kAuto,           // Sibernetic's rule: swimming waves if the configuration's name says "worm"
  kOff,            // all activations zero
  kSwimmingWaves,  // main_sim.MuscleSimulation, whatever the name
};

// The activations MuscleSimulation.run() returns on its n-th call (n = 0, 1, ...), each cast to
// float as Sibernetic's host does. Rows 0..11 of four quadrants (MDR, MVR, MVL, MDL; two muscles
// per row), a ramp over the first 2500 calls, crawling waves after call 1,200,000.
std::array<float, kMuscleCount> MuscleSimulationSignal(double n);

// Sibernetic's isWormConfig(): the configuration file's name contains "worm". owval's reference
// folders keep each run's file as <scenario>/configuration, so there the folder's name counts.
bool NamesAWorm(const std::string& configuration_path);
// Whether `signal` drives the muscles of the configuration read from `configuration_path`:
// waves, or auto for a configuration named after the worm.
bool DrivesMuscles(MuscleSignal signal, const std::string& configuration_path);

// "auto", "off" or "waves", as flags, run requests, checkpoints and fit histories name a
// signal; any other name is InputError. MuscleSignalName is its inverse.
MuscleSignal ParseMuscleSignal(const std::string& name);
const char* MuscleSignalName(MuscleSignal signal);

}  // namespace owval::engine
