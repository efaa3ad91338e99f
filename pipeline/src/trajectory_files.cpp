#include "trajectory_files.hpp"

#include <memory>

#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval::pipeline {
namespace fs = std::filesystem;
namespace {

TrajectoryHeader HeaderOf(const Trajectory& t) {
  return {t.box, t.time_step_s, t.log_step, t.type, t.provenance};
}

// Appends the engine's frames to one file. The writer opens at the first frame, when the run
// shows which fields it records (the in-memory run's trajectory had exactly those).
class FileSink : public engine::FrameSink {
 public:
  explicit FileSink(fs::path destination) : destination_(std::move(destination)) {}
  void Begin(const Trajectory& header, int threads) override {
    header_ = HeaderOf(header);
    options_.hdf5.threads = threads;
  }
  void Frame(const engine::FrameView& f) override {
    if (!writer_) {
      header_.velocities = !f.velocities.empty();
      header_.density = !f.density.empty();
      header_.pressure = !f.pressure.empty();
      writer_ = OpenTrajectoryWriter(destination_, header_, options_);
    }
    writer_->AppendFrame(f.time_s, f.positions.data(), Data(f.velocities), Data(f.density),
                         Data(f.pressure));
  }
  void Close() {
    if (!writer_) writer_ = OpenTrajectoryWriter(destination_, header_, options_);
    writer_->Close();
  }

 private:
  static const float* Data(std::span<const float> values) {
    return values.empty() ? nullptr : values.data();
  }
  fs::path destination_;
  TrajectoryHeader header_;
  TrajectoryWriterOptions options_;
  std::unique_ptr<TrajectoryWriter> writer_;
};

// A per-frame field of the frame a FrameRef names, or null when the source holds none.
const float* FieldAt(const std::vector<float>& field, const FrameRef& frame,
                     std::size_t values_per_particle) {
  if (field.empty()) return nullptr;
  return field.data() + frame.frame * frame.trajectory.particle_count() * values_per_particle;
}

}  // namespace

engine::RunSummary RunIntoFile(const engine::SiberneticConfig& config,
                               const engine::RunOptions& options, const fs::path& destination) {
  FileSink sink(destination);
  const engine::RunSummary summary = engine::Run(config, options, &sink);
  sink.Close();
  return summary;
}

void CopyTrajectoryFile(const fs::path& source, const fs::path& destination,
                        const TextReadOptions& read) {
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(source, read);
  frames->ReadFields();
  TrajectoryHeader header = HeaderOf(frames->header());
  std::unique_ptr<TrajectoryWriter> writer;
  for (std::size_t f = 0; f < frames->frame_count(); ++f) {
    const FrameRef frame = frames->Frame(f);
    const Trajectory& t = frame.trajectory;
    if (!writer) {  // the fields the source holds are known once a frame is read
      header.velocities = t.has_velocities();
      header.density = t.has_density();
      header.pressure = t.has_pressure();
      writer = OpenTrajectoryWriter(destination, header);
    }
    writer->AppendFrame(t.time_s[frame.frame], t.position(frame.frame, 0),
                        FieldAt(t.velocities, frame, 3), FieldAt(t.density, frame, 1),
                        FieldAt(t.pressure, frame, 1));
  }
  if (!writer) writer = OpenTrajectoryWriter(destination, header);
  writer->Close();
}

std::unique_ptr<FrameSource> OpenQuietly(const fs::path& file) {
  TextReadOptions quiet;
  quiet.quiet = true;
  return OpenFrameSource(file, quiet);
}

TrackedSeries ReadTrackedSeries(const fs::path& file, const Track& track) {
  return owval::ReadTrackedSeries(*OpenQuietly(file), track);
}

}  // namespace owval::pipeline
