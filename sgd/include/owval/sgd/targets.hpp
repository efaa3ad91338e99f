#pragma once
// What a fit matches: trajectory metrics of a tracked signal, each as a scaled residual
// sqrt(weight)·(measured − target)/scale, so the loss is Σ weight·((measured − target)/scale)².
// And how runs are produced for a parameter vector: any Simulator, e.g. an external command that
// writes a trajectory file (so the same fitter tunes a Metal or CUDA port). Targets read only the
// tracked series (trajectory/tracked_series.hpp), so that is all an evaluation or a reference
// keeps: memory O(particles) + one number a frame, whatever the run's length.
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "owval/sgd/fit.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/tracked_series.hpp"

namespace owval::sgd {

struct Target {
  // period (s) | half_amplitude (cu) | equilibrium (cu) | rms (cu, against `reference_file`)
  std::string metric;
  double value = 0;
  double scale = 1;
  double weight = 1;
  std::string reference_file;  // rms only
  // rms: the tracked series of reference_file, read frame by frame once by LoadReferences
  // (MakeObjective calls it) so that concurrent evaluations share it instead of each reading
  // the file.
  std::shared_ptr<const TrackedSeries> reference;
};

// Reads the tracked series of every rms target's reference_file that is not loaded yet
// (InputError when unreadable or when the track names nothing in it). Call it on the thread
// that owns the fit, before evaluations run concurrently: reading HDF5 forks a containment child
// (trajectory/hdf5_format.cpp), and a fork while evaluation threads allocate can leave the child
// waiting on a lock the fork did not copy the owner of.
void LoadReferences(const Track& track, std::vector<Target>* targets);

// "period=0.7246e-3:scale=0.725e-3:weight=0.25" and "rms=0:scale=1:ref=FILE".
Target ParseTarget(const std::string& text);
// "elasticity_coefficient=1.62e8:log" or "name=start[:log|:lin][:lower:upper]".
Parameter ParseParameter(const std::string& text);

// The targets measured on one run's tracked series (`track`: what an rms reference not loaded
// yet is read with).
std::vector<double> ScaledResiduals(const TrackedSeries& run, const Track& track,
                                    const std::vector<Target>& targets);
nlohmann::json TargetsToJson(const std::vector<Target>& targets, const Track& track);

// Parameter values → the tracked series of the run they make. Must be safe to call from several
// threads at once (finite-difference points run concurrently).
using Simulator =
    std::function<TrackedSeries(const std::vector<double>& values, const Track& track)>;

// Objective = simulate, then measure the targets. Loads the targets' references first.
Objective MakeObjective(Simulator simulator, Track track, std::vector<Target> targets);

// Runs `command_template` through the shell for each evaluation, with {name} replaced by each
// parameter's value, {out} by a fresh directory under work_dir and {out_file} by a trajectory
// path inside it; then reads the tracked series of {out_file} if it was written, else of the
// first of trajectory.h5 and position_buffer.txt found in {out}, frame by frame. A non-zero exit
// status is an InputError.
Simulator CommandSimulator(std::string command_template, std::vector<Parameter> parameters,
                           std::filesystem::path work_dir);

}  // namespace owval::sgd
