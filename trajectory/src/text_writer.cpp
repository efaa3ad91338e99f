// Streaming Sibernetic text output (writer.hpp): rows appended, 4 MiB buffered.
#include <fstream>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/trajectory/writer.hpp"
#include "text_rows.hpp"
#include "writers.hpp"

namespace owval::internal {
namespace {

class TextWriter : public TrajectoryWriter {
 public:
  TextWriter(const std::filesystem::path& destination, const TrajectoryHeader& header,
             TextLayout layout)
      : out_(destination), type_(header.type), native_(layout == TextLayout::kNative) {
    for (float t : type_) moving_ += KindOf(t) != ParticleKind::kBoundary;
    if (!native_)
      for (std::size_t i = 0; i < moving_; ++i)
        if (KindOf(type_[i]) == ParticleKind::kBoundary)
          throw InputError(destination.string(), 0,
                           "cannot write the opencl layout: boundary particles must come last");
    buffer_ = TextHeader(header.box, header.type, header.time_step_s, header.log_step);
  }

  void AppendFrame(double, const float* positions, const float*, const float*,
                   const float*) override {
    const std::size_t rows = (frames_ == 0 || native_) ? type_.size() : moving_;
    for (std::size_t i = 0; i < rows; ++i) AppendRow(buffer_, positions + 3 * i, type_[i]);
    ++frames_;
    if (buffer_.size() > (4u << 20)) Flush();
  }

  void Close() override {
    Flush();
    out_.Commit();
  }

  void FinishInto(OutputGroup* group) override {
    Flush();
    group->Adopt(&out_);
  }

  void Abort() override {
    Flush();
    out_.CommitAs(PartialPath(out_.destination()));
  }

  std::size_t frames_written() const override { return frames_; }

  WriterCheckpoint Checkpoint() override {
    Flush();
    WriterCheckpoint c;
    c.file = out_.temporary_path().filename().string();
    c.frames = frames_;
    c.bytes = std::filesystem::file_size(out_.temporary_path());
    out_.KeepOnFailure();
    return c;
  }

  // Continues `file`, already cut back to the checkpoint, after `frames` frames.
  void Continue(const std::filesystem::path& file, std::size_t frames) {
    out_.Adopt(file);
    frames_ = frames;
    buffer_.clear();
  }

 private:
  void Flush() {
    std::ofstream& stream = out_.stream();
    stream.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    stream.flush();
    if (!stream) throw InputError(out_.destination().string(), 0, "write failed (disk full?)");
    buffer_.clear();
  }

  AtomicOutput out_;
  std::vector<float> type_;
  std::size_t moving_ = 0, frames_ = 0;
  bool native_;
  std::string buffer_;
};

}  // namespace

std::filesystem::path CheckpointedFile(const std::filesystem::path& destination,
                                       const WriterCheckpoint& checkpoint) {
  const std::filesystem::path file = destination.parent_path() / checkpoint.file;
  if (!checkpoint.file.empty() && checkpoint.file.find('/') == std::string::npos &&
      std::filesystem::is_regular_file(file))
    return file;
  const std::filesystem::path partial = PartialPath(destination);
  if (std::filesystem::is_regular_file(partial)) return partial;
  throw InputError(destination.string(), 0,
                   "cannot resume: neither " + file.string() + " nor " + partial.string() +
                       " exists (the output of the checkpointed run)");
}

void CheckTextResumable(const std::filesystem::path& destination,
                        const WriterCheckpoint& checkpoint) {
  const std::filesystem::path file = CheckpointedFile(destination, checkpoint);
  if (std::filesystem::file_size(file) < checkpoint.bytes)
    throw InputError(file.string(), 0,
                     "cannot resume: shorter than the checkpoint's " +
                         std::to_string(checkpoint.bytes) + " bytes");
}

std::unique_ptr<TrajectoryWriter> ResumeTextWriter(const std::filesystem::path& destination,
                                                   const TrajectoryHeader& header,
                                                   TextLayout layout,
                                                   const WriterCheckpoint& checkpoint) {
  CheckTextResumable(destination, checkpoint);
  const std::filesystem::path file = CheckpointedFile(destination, checkpoint);
  std::filesystem::resize_file(file, checkpoint.bytes);
  auto writer = std::make_unique<TextWriter>(destination, header, layout);
  writer->Continue(file, checkpoint.frames);
  return writer;
}

std::unique_ptr<TrajectoryWriter> OpenTextWriter(const std::filesystem::path& destination,
                                                 const TrajectoryHeader& header,
                                                 TextLayout layout) {
  return std::make_unique<TextWriter>(destination, header, layout);
}

}  // namespace owval::internal

namespace owval {
namespace {

// The writers' one rule for the format: an HDF5 file by its extension, else Sibernetic text.
bool WritesHdf5(const std::filesystem::path& destination) {
  const std::string ext = destination.extension().string();
  return ext == ".h5" || ext == ".hdf5";
}

}  // namespace

std::filesystem::path PartialPath(const std::filesystem::path& destination) {
  std::filesystem::path partial = destination;
  partial.replace_filename(destination.stem().string() + ".partial" +
                           destination.extension().string());
  return partial;
}

bool IsPartialPath(const std::filesystem::path& path) {
  return path.stem().extension() == ".partial";
}

std::unique_ptr<TrajectoryWriter> ResumeTrajectoryWriter(const std::filesystem::path& destination,
                                                         const TrajectoryHeader& header,
                                                         const WriterCheckpoint& checkpoint,
                                                         const TrajectoryWriterOptions& options) {
  if (WritesHdf5(destination))
    return internal::ResumeHdf5Writer(destination, header, options.hdf5, checkpoint);
  return internal::ResumeTextWriter(
      destination, header,
      options.layout == TextLayout::kAuto ? TextLayout::kOpenCL : options.layout, checkpoint);
}

void CheckResumable(const std::filesystem::path& destination, const TrajectoryHeader& header,
                    const WriterCheckpoint& checkpoint) {
  if (WritesHdf5(destination))
    internal::CheckHdf5Resumable(destination, header, checkpoint);
  else
    internal::CheckTextResumable(destination, checkpoint);
}

std::unique_ptr<TrajectoryWriter> OpenTrajectoryWriter(const std::filesystem::path& destination,
                                                       const TrajectoryHeader& header,
                                                       const TrajectoryWriterOptions& options) {
  if (header.type.empty())
    throw InputError(destination.string(), 0, "a trajectory needs at least one particle");
  if (WritesHdf5(destination)) return internal::OpenHdf5Writer(destination, header, options.hdf5);
  return internal::OpenTextWriter(
      destination, header,
      options.layout == TextLayout::kAuto ? TextLayout::kOpenCL : options.layout);
}

}  // namespace owval
