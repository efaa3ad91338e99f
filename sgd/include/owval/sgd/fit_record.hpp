#pragma once
// What a fit simulated, recorded in history.json's "simulation" object (schema
// owval.fit.history/2, docs/fit_history.md), and the one rerun of its best iterate that the PR
// checklist's item 6 makes from that record. A history whose numbers only agree with each other
// proves nothing (invented residuals and their squares agree); rerun through the same simulator
// and loss as the fit, its best residuals must come out again.
//
// The configuration is written next to history.json (configuration.txt, atomically) and named
// with its FNV-1a 64 hash (Fowler, Noll & Vo, http://www.isthe.com/chongo/tech/comp/fnv/): a
// check that the file is the one the fit ran, not a defence against a chosen collision (the
// rerun itself is the evidence; the hash makes a swapped file fail as "not verified" instead of
// as a disagreement).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "owval/backends/registry.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/track.hpp"
#include "owval/trajectory/tracked_series.hpp"

namespace owval::sgd {

inline constexpr const char* kFitHistorySchema = "owval.fit.history/2";
inline constexpr const char* kFitConfigurationFile = "configuration.txt";

// FNV-1a 64 of `bytes`, 16 lower-case hex digits.
std::string Fnv1a64Hex(std::string_view bytes);
// The same over a file's bytes, read in blocks (a reference trajectory may be large).
// InputError when it cannot be read.
std::string FileFnv1a64Hex(const std::filesystem::path& file);

// Writes `config` to fit_dir/configuration.txt (atomically) and returns the record naming it:
// {"file": "configuration.txt", "fnv1a64": ..., "source": config.source} (the source name is
// kept because the engine's muscle rule reads it: "worm" in the name drives the muscles).
nlohmann::json RecordConfiguration(const engine::SiberneticConfig& config,
                                   const std::filesystem::path& fit_dir);

// "simulation" of a finite-difference fit run by the engine: {"kind": "engine", backend,
// configuration, duration_s, log_step, integrator, muscles, apply_physical_parameters,
// constants (every constant that differs from Sibernetic's default, by owval's name)}.
nlohmann::json EngineSimulationJson(const engine::RunOptions& run,
                                    const nlohmann::json& configuration);

// "simulation" of a gradient fit (XPBD's differentiable model): {"kind": "xpbd_model",
// configuration, steps, loss: {reference: {file, fnv1a64}, track, groups, scale}}.
nlohmann::json ModelSimulationJson(const nlohmann::json& configuration, std::size_t steps,
                                   const std::filesystem::path& reference_file, const Track& track,
                                   const std::vector<std::string>& groups, double scale_cu);

// The engine run options of one fit evaluation at `values`: `base` on one thread, positions
// only, each parameter set by name. EngineSimulator runs exactly these; so does the rerun.
engine::RunOptions EvaluationRunOptions(engine::RunOptions base,
                                        const std::vector<std::string>& parameter_names,
                                        const std::vector<double>& values);

struct FitRerun {
  // Why the history cannot be rerun ("no \"simulation\" record", "configuration.txt does not
  // match its recorded hash", ...); empty when the rerun ran.
  std::string not_verified;
  std::vector<double> residuals;  // at the best iterate, as the fit scores them
  double loss = 0;                // Σ residuals²
  std::string simulated;          // what was run, in words, for the report
  // The history's best iteration as recorded (the one rerun): its "loss" and "residuals" are
  // what the rerun must give back.
  nlohmann::json best_iteration;
};

struct FitRerunOptions {
  // The tracked series rms targets are measured against: the reviewed directory's reference,
  // never the path the history names. Null: an rms target cannot be rerun (not verified).
  std::shared_ptr<const TrackedSeries> rms_reference;
  // The trajectory a gradient fit's ("xpbd_model") loss is measured against: the reviewed
  // directory's reference, which the caller has held to the record's FNV-1a 64 (the checklist
  // hashes it once), never the path the history names. Null: such a fit is not verified.
  FrameSource* loss_reference = nullptr;
  // The registry entry a fit of a named backend ("backend") is rerun through: the caller's own
  // (owval checklist --fit-backend NAME), never the template the history records. Null: such a
  // fit is not verified.
  const backends::Backend* backend = nullptr;
  // Called with (steps done, total steps) during the engine run; may be empty.
  std::function<void(std::size_t, std::size_t)> on_step;
};

// Reruns `history`'s best iterate (final.parameters) once with its recorded simulation, through
// the fit's own simulator and loss (EngineSimulator's run options and ScaledResiduals, the
// caller's backend entry with the recorded configuration and run and ScaledResiduals, or the
// gradient fit's model loss). `fit_dir` holds history.json and the configuration file.
FitRerun RerunBestIterate(const nlohmann::json& history, const std::filesystem::path& fit_dir,
                          const FitRerunOptions& options);

}  // namespace owval::sgd
