#pragma once
// `owval inspect` as a library call: phase 3's measurements of one tracked coordinate (period,
// amplitude, equilibrium, drift, damping, settling) and, for a worm, its kinematics. The file is
// read frame by frame (memory O(particles), whatever its length).
//
//   const pipeline::Inspection i = pipeline::InspectTrajectory("run/trajectory.h5", {}, Track{},
//   {}); std::cout << i.ToText();
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "owval/compare/signal_metrics.hpp"
#include "owval/kinematics/kinematics.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/track.hpp"

namespace owval::pipeline {

struct Inspection {
  std::filesystem::path file;
  std::string layout;   // what was read, e.g. "Sibernetic text, opencl layout" (TextReadReport)
  std::string subject;  // the tracked quantity, e.g. "particle 0 y"
  compare::SignalMetrics metrics;
  std::optional<kinematics::Report> worm;  // a worm's kinematics (issue 15)

  nlohmann::json ToJson() const;
  std::string ToText() const;
};

// InputError for an unreadable file, a track that names nothing in it, too few frames.
Inspection InspectTrajectory(const std::filesystem::path& path, const TextReadOptions& read,
                             const Track& track, const compare::SignalWindow& window);

}  // namespace owval::pipeline
