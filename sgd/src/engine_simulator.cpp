#include "owval/sgd/engine_simulator.hpp"

#include <memory>

#include "owval/engine/constants.hpp"
#include "owval/sgd/fit_record.hpp"

namespace owval::sgd {
namespace {

// Measures the tracked value of each frame as the engine produces it.
class TrackedSeriesSink : public engine::FrameSink {
 public:
  explicit TrackedSeriesSink(const Track& track) : track_(track) {}
  void Begin(const Trajectory& header, int /*threads*/) override {
    recorder_ = std::make_unique<TrackedSeriesRecorder>(header, track_);
  }
  void Frame(const engine::FrameView& f) override { recorder_->Add(f.time_s, f.positions.data()); }
  TrackedSeries Take() { return recorder_ ? recorder_->Take() : TrackedSeries{}; }

 private:
  const Track& track_;
  std::unique_ptr<TrackedSeriesRecorder> recorder_;
};

}  // namespace

void SetConstant(engine::PhysicsConstants* c, const std::string& name, double value) {
  engine::SetConstant(c, name, value);
}

TrackedSeries RunTrackedSeries(const engine::SiberneticConfig& config,
                               const engine::RunOptions& options, const Track& track) {
  engine::RunOptions positions_only = options;
  positions_only.record_fields = false;
  TrackedSeriesSink sink(track);
  engine::Run(config, positions_only, &sink);
  return sink.Take();
}

Simulator EngineSimulator(engine::SiberneticConfig config, engine::RunOptions base,
                          std::vector<Parameter> parameters) {
  std::vector<std::string> names;
  for (const Parameter& p : parameters) {
    engine::SetConstant(&base.constants, p.name, p.start);  // validate names now
    names.push_back(p.name);
  }
  return [config = std::move(config), base, names](const std::vector<double>& values,
                                                   const Track& track) {
    return RunTrackedSeries(config, EvaluationRunOptions(base, names, values), track);
  };
}

}  // namespace owval::sgd
