#pragma once
// What a fit matches: trajectory metrics of a tracked signal, each as a scaled residual
// sqrt(weight)·(measured − target)/scale, so the loss is Σ weight·((measured − target)/scale)².
// And how trajectories are produced for a parameter vector: any Simulator, e.g. an external
// command that writes a trajectory file (so the same fitter tunes a Metal or CUDA port).
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/sgd/fit.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/trajectory.hpp"

namespace owval::sgd {

struct Target {
  // period (s) | half_amplitude (cu) | equilibrium (cu) | rms (cu, against `reference_file`)
  std::string metric;
  double value = 0;
  double scale = 1;
  double weight = 1;
  std::string reference_file;  // rms only
  // rms: the trajectory in reference_file, read once by LoadReferences (MakeObjective calls it)
  // so that concurrent evaluations share it instead of each reading the file.
  std::shared_ptr<const Trajectory> reference;
};

// Reads every rms target's reference_file that is not loaded yet (InputError when unreadable).
// Call it on the thread that owns the fit, before evaluations run concurrently: reading HDF5
// forks a containment child (trajectory/hdf5_format.cpp), and a fork while evaluation threads
// allocate can leave the child waiting on a lock the fork did not copy the owner of.
void LoadReferences(std::vector<Target>* targets);

// "period=0.7246e-3:scale=0.725e-3:weight=0.25" and "rms=0:scale=1:ref=FILE".
Target ParseTarget(const std::string& text);
// "elasticity_coefficient=1.62e8:log" or "name=start[:log|:lin][:lower:upper]".
Parameter ParseParameter(const std::string& text);

std::vector<double> ScaledResiduals(const Trajectory& trajectory, const Track& track,
                                    const std::vector<Target>& targets);
nlohmann::json TargetsToJson(const std::vector<Target>& targets, const Track& track);

using Simulator = std::function<Trajectory(const std::vector<double>& values)>;

// Objective = simulate, then measure the targets. Loads the targets' references first.
Objective MakeObjective(Simulator simulator, Track track, std::vector<Target> targets);

// Runs `command_template` through the shell for each evaluation, with {name} replaced by each
// parameter's value, {out} by a fresh directory under work_dir and {out_file} by a trajectory
// path inside it; then reads {out_file} if it was written, else the first of trajectory.h5 and
// position_buffer.txt found in {out}. A non-zero exit status is an InputError.
Simulator CommandSimulator(std::string command_template, std::vector<Parameter> parameters,
                           std::filesystem::path work_dir);

}  // namespace owval::sgd
