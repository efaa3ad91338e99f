// Frame sources (frame_source.hpp): a trajectory in memory, an HDF5 file through
// Hdf5FrameReader, Sibernetic text through text_stream.cpp.
#include "owval/trajectory/frame_source.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/trajectory/writer.hpp"
#include "text_stream.hpp"

namespace owval {
namespace {

std::size_t ValuesPerParticle(const std::string& array) {
  return array == "density" || array == "pressure" ? 1 : 3;
}

class MemorySource : public FrameSource {
 public:
  explicit MemorySource(const Trajectory& t) : t_(t) {}
  const Trajectory& header() const override { return t_; }
  FrameRef Frame(std::size_t f) override {
    if (f >= t_.frame_count()) throw std::out_of_range("memory frame source: frame past the end");
    return {t_, f};
  }

 private:
  const Trajectory& t_;
};

class Hdf5Source : public FrameSource {
 public:
  explicit Hdf5Source(const std::filesystem::path& path) : reader_(path) {
    const TrajectoryHeader& h = reader_.header();
    for (Trajectory* t : {&header_, &frame_}) {
      t->box = h.box;
      t->time_step_s = h.time_step_s;
      t->log_step = h.log_step;
      t->type = h.type;
      t->provenance = h.provenance;
    }
    header_.time_s = reader_.time_s();
    frame_.time_s.assign(1, 0.0);
    frame_.positions.assign(3 * h.type.size(), 0.0f);
  }
  const Trajectory& header() const override { return header_; }
  FrameRef Frame(std::size_t f) override {
    if (f >= header_.frame_count())
      throw std::out_of_range("HDF5 frame source: frame past the end");
    if (f != current_) {
      current_ = SIZE_MAX;  // until every read succeeds
      frame_.time_s[0] = reader_.ReadFrame(f, frame_.positions.data());
      ReadFieldsOf(f);
      current_ = f;
    }
    return {frame_, 0};
  }
  void CopyFrames(const std::string& array, std::size_t first, std::size_t count,
                  float* out) override {
    const std::size_t values = ValuesPerParticle(array) * header_.particle_count();
    for (std::size_t f = first; f < first + count; ++f, out += values)
      if (array == "positions")
        reader_.ReadFrame(f, out);  // the same finiteness check as Frame()
      else
        reader_.ReadField(array, f, out);
  }
  void ReadFields() override {
    const TrajectoryHeader& h = reader_.header();
    const std::size_t n = h.type.size();
    frame_.velocities.assign(h.velocities ? 3 * n : 0, 0.0f);
    frame_.density.assign(h.density ? n : 0, 0.0f);
    frame_.pressure.assign(h.pressure ? n : 0, 0.0f);
    current_ = SIZE_MAX;
  }
  // The text format's partial mark is its name; HDF5 carries it, and so may be renamed.
  void MarkPartial() { header_.provenance["partial"].assign(1, '1'); }

 private:
  void ReadFieldsOf(std::size_t f) {
    if (frame_.has_velocities()) reader_.ReadField("velocities", f, frame_.velocities.data());
    if (frame_.has_density()) reader_.ReadField("density", f, frame_.density.data());
    if (frame_.has_pressure()) reader_.ReadField("pressure", f, frame_.pressure.data());
  }

  Hdf5FrameReader reader_;
  Trajectory header_, frame_;
  std::size_t current_ = SIZE_MAX;
};

}  // namespace

void FrameSource::CopyFrames(const std::string& array, std::size_t first, std::size_t count,
                             float* out) {
  const std::size_t values = ValuesPerParticle(array) * particle_count();
  for (std::size_t f = first; f < first + count; ++f, out += values) {
    const FrameRef frame = Frame(f);
    const Trajectory& t = frame.trajectory;
    const std::vector<float>& from = array == "positions"    ? t.positions
                                     : array == "velocities" ? t.velocities
                                     : array == "density"    ? t.density
                                                             : t.pressure;
    if (from.size() < (frame.frame + 1) * values)
      throw std::out_of_range("frame source: no " + array + " in frame " + std::to_string(f));
    std::copy(from.begin() + std::ptrdiff_t(frame.frame * values),
              from.begin() + std::ptrdiff_t((frame.frame + 1) * values), out);
  }
}

std::unique_ptr<FrameSource> MemoryFrameSource(const Trajectory& trajectory) {
  return std::make_unique<MemorySource>(trajectory);
}

void RequireFrames(const FrameSource& frames, const std::filesystem::path& file,
                   std::size_t at_least) {
  if (frames.frame_count() < at_least)
    throw InputError(file.string(), 0,
                     "holds " + std::to_string(frames.frame_count()) +
                         " frame(s); expected at least " + std::to_string(at_least));
}

std::unique_ptr<FrameSource> OpenFrameSource(const std::filesystem::path& path,
                                             const TextReadOptions& options,
                                             TextReadReport* report) {
  // As ReadTrajectory: the partial mark from the name too (PartialPath), said in the report.
  const bool named_partial = IsPartialPath(path);
  std::unique_ptr<FrameSource> source;
  if (DetectFormat(path) == FileFormat::kHdf5) {
    auto h5 = std::make_unique<Hdf5Source>(path);
    if (named_partial) h5->MarkPartial();
    if (report)
      report->description = "owval HDF5: " + std::to_string(h5->frame_count()) + " frames, " +
                            std::to_string(h5->particle_count()) + " particles";
    source = std::move(h5);
  } else {
    source = internal::OpenTextFrameSource(path.string(), options, report, named_partial);
  }
  if (report && source->partial()) report->description += " (partial: an interrupted run's)";
  return source;
}

}  // namespace owval
