// RunToFiles: engine::Run streamed into the output directory, with checkpoints and resume.
#include "owval/engine/long_run.hpp"

#include <libdeflate.h>
#include <malloc.h>

#include <cstring>
#include <fstream>
#include <memory>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/trajectory/writer.hpp"
#include "state/state_io.hpp"

namespace owval::engine {
namespace fs = std::filesystem;
namespace {

constexpr char kCheckpointMagic[8] = {'O', 'W', 'V', 'L', 'R', 'U', 'N', '1'};
// 2: the file ends with the CRC-32 of every byte before it.
constexpr std::uint32_t kCheckpointVersion = 2;

// What a checkpoint holds (long_run.hpp).
struct CheckpointFile {
  std::string invocation;
  std::uint64_t fingerprint = 0, steps = 0, frames = 0;
  std::vector<WriterCheckpoint> writers;
  std::string solver_state;
};

// FNV-1a 64 over the box, positions, velocities and connections: the same configuration.
std::uint64_t Fingerprint(const SiberneticConfig& c) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* data, std::size_t bytes) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(&c.box, sizeof c.box);
  mix(c.position.data(), c.position.size() * sizeof(Row4));
  mix(c.velocity.data(), c.velocity.size() * sizeof(Row4));
  mix(c.connection.data(), c.connection.size() * sizeof(Row4));
  return h;
}

// Written piece by piece into the file: the solver state and pending frames (megabytes) are
// not copied into one buffer first.
void WriteCheckpoint(const fs::path& path, const CheckpointFile& c,
                     const std::string& solver_state) {
  AtomicOutput file(path);
  std::ofstream& out = file.stream();
  std::uint32_t crc = 0;
  auto put = [&out, &crc](const std::string& bytes) {
    out.write(bytes.data(), std::streamsize(bytes.size()));
    crc = libdeflate_crc32(crc, bytes.data(), bytes.size());
  };
  auto blob = [&](const std::string& bytes) {
    std::string size;
    internal::StateWriter(&size).Put(std::uint64_t(bytes.size()));
    put(size), put(bytes);
  };
  std::string head;
  internal::StateWriter w(&head);
  for (char ch : kCheckpointMagic) w.Put(ch);
  w.Put(kCheckpointVersion), w.Put(c.invocation), w.Put(c.fingerprint), w.Put(c.steps);
  w.Put(c.frames), w.Put(std::uint64_t(c.writers.size()));
  put(head);
  for (const WriterCheckpoint& k : c.writers) {
    std::string fields;
    internal::StateWriter f(&fields);
    f.Put(k.file), f.Put(k.frames), f.Put(k.bytes), f.Put(k.file_frames);
    put(fields), blob(k.pending);
  }
  blob(solver_state);
  std::string tail;
  internal::StateWriter(&tail).Put(crc);
  put(tail);
  file.Commit();
}

// A byte flipped in the solver's state resumed the run from an altered state and said nothing:
// the file's last four bytes are the CRC-32 of all before them.
void CheckCrc(const std::string& bytes, internal::StateReader* r) {
  std::uint32_t stored = 0;
  if (bytes.size() < sizeof stored) r->Fail("truncated");
  const std::size_t body = bytes.size() - sizeof stored;
  std::memcpy(&stored, bytes.data() + body, sizeof stored);
  if (libdeflate_crc32(0, bytes.data(), body) != stored)
    r->Fail("its CRC-32 does not match its contents: the file was altered or damaged");
}

CheckpointFile Load(const fs::path& out) {
  const fs::path path = CheckpointPath(out);
  const std::string bytes = ReadWholeFile(path);
  internal::StateReader r(bytes, path.string());
  char magic[8];
  for (char& ch : magic) r.Get(&ch);
  if (std::string(magic, 8) != std::string(kCheckpointMagic, 8)) r.Fail("not an owval checkpoint");
  std::uint32_t version = 0;
  r.Get(&version);
  if (version != kCheckpointVersion)
    r.Fail("format version " + std::to_string(version) + ", this build reads " +
           std::to_string(kCheckpointVersion));
  CheckCrc(bytes, &r);
  CheckpointFile c;
  std::uint64_t writers = 0;
  r.Get(&c.invocation), r.Get(&c.fingerprint), r.Get(&c.steps), r.Get(&c.frames), r.Get(&writers);
  if (writers != LongRunOutputs(out).size()) r.Fail("wrong number of outputs");
  c.writers.resize(writers);
  for (WriterCheckpoint& k : c.writers) {
    r.Get(&k.file), r.Get(&k.frames), r.Get(&k.bytes), r.Get(&k.file_frames), r.Get(&k.pending);
    if (k.frames != c.frames) r.Fail("an output's frame count differs from the run's");
  }
  r.Get(&c.solver_state);
  std::uint32_t crc = 0;  // checked above
  r.Get(&crc);
  if (!r.done()) r.Fail("bytes left after the checksum");
  return c;
}

// Writes every frame into the outputs; checkpoints them with the solver's state.
class FileSink : public FrameSink {
 public:
  FileSink(const LongRunOptions& o, std::uint64_t fingerprint, const CheckpointFile* resume)
      : o_(o), fingerprint_(fingerprint), resume_(resume) {}

  void Begin(const Trajectory& t, int threads) override {
    TrajectoryHeader h{t.box, t.time_step_s, t.log_step, t.type, t.provenance};
    h.velocities = h.density = h.pressure = fields_;
    TrajectoryWriterOptions options;
    options.hdf5.threads = threads;
    const std::vector<fs::path> outputs = LongRunOutputs(o_.out);
    if (resume_)  // all before any: a refused resumption leaves every output as it was
      for (std::size_t i = 0; i < outputs.size(); ++i)
        CheckResumable(outputs[i], h, resume_->writers[i]);
    for (std::size_t i = 0; i < outputs.size(); ++i)
      writers_.push_back(resume_
                             ? ResumeTrajectoryWriter(outputs[i], h, resume_->writers[i], options)
                             : OpenTrajectoryWriter(outputs[i], h, options));
    if (o_.on_begin) o_.on_begin(t);
  }

  void Frame(const FrameView& f) override {
    const float* v = f.velocities.empty() ? nullptr : f.velocities.data();
    const float* d = f.density.empty() ? nullptr : f.density.data();
    const float* p = f.pressure.empty() ? nullptr : f.pressure.data();
    for (auto& w : writers_) w->AppendFrame(f.time_s, f.positions.data(), v, d, p);
    if (o_.on_frame) o_.on_frame(f);
  }

  void Checkpoint(std::size_t steps, std::size_t frames, const std::string& state,
                  bool stopping) override {
    {
      CheckpointFile c{o_.invocation, fingerprint_, steps, frames, {}, {}};
      for (auto& w : writers_)
        c.writers.push_back(stopping ? w->StopCheckpoint() : w->Checkpoint());
      WriteCheckpoint(CheckpointPath(o_.out), c, state);
    }
    // The checkpoint's buffers (solver state, pending frames: megabytes) are freed; give the
    // pages back so that peak memory stays the run's, not the sum of its checkpoints'.
    ::malloc_trim(0);
  }

  void set_fields(bool fields) { fields_ = fields; }
  // The outputs are one set: finished under their temporary names, then moved into place
  // together (OutputGroup).
  void FinishInto(OutputGroup* group) {
    for (auto& w : writers_) w->FinishInto(group);
  }
  void Abort() {
    for (auto& w : writers_) w->Abort();
  }

 private:
  const LongRunOptions& o_;
  std::uint64_t fingerprint_;
  const CheckpointFile* resume_;
  bool fields_ = true;
  std::vector<std::unique_ptr<TrajectoryWriter>> writers_;
};

// Before any work: a fresh run does not overwrite an interrupted run's checkpoint (it could no
// longer be resumed), and the checkpoint's place is not a directory.
void CheckCheckpointPath(const LongRunOptions& long_run) {
  const fs::path checkpoint = CheckpointPath(long_run.out);
  std::error_code error;
  if (!long_run.resume && fs::is_regular_file(checkpoint, error))
    throw InputError(long_run.out.string(), 0,
                     "holds an interrupted run's checkpoint; continue it with owval run --resume " +
                         long_run.out.string() + ", or remove " +
                         checkpoint.parent_path().string() + " to start afresh");
  if (!long_run.resume) CheckOutputPath(checkpoint);
}

}  // namespace

fs::path CheckpointPath(const fs::path& out) { return out / "checkpoint" / "checkpoint.bin"; }

std::vector<fs::path> LongRunOutputs(const fs::path& out) {
  return {out / "position_buffer.txt", out / "trajectory.h5"};
}

std::string ReadCheckpointInvocation(const fs::path& out) { return Load(out).invocation; }

RunSummary RunToFiles(const SiberneticConfig& config, const RunOptions& run_options,
                      const LongRunOptions& long_run) {
  CheckCheckpointPath(long_run);
  const std::uint64_t fingerprint = Fingerprint(config);
  CheckpointFile resume;
  RunOptions options = run_options;
  if (long_run.resume) {
    resume = Load(long_run.out);
    if (resume.fingerprint != fingerprint)
      throw InputError(
          CheckpointPath(long_run.out).string(), 0,
          "the checkpoint was written for another configuration than " + config.source);
    options.resume_state = resume.solver_state;
    options.resume_source = CheckpointPath(long_run.out).string();
  }
  FileSink sink(long_run, fingerprint, long_run.resume ? &resume : nullptr);
  sink.set_fields(options.record_fields);
  RunSummary summary;
  try {
    summary = Run(config, options, &sink);
  } catch (const SimulationError&) {
    sink.Abort();  // what was written, readable, beside the state dump
    throw;
  }
  if (summary.interrupted) {
    sink.Abort();
  } else {
    OutputGroup own;
    sink.FinishInto(long_run.outputs ? long_run.outputs : &own);
    if (!long_run.outputs) own.Commit();
    // Complete: a checkpoint would name temporaries that no longer exist. Only the file goes;
    // its directory too when nothing else is in it (a user's files there stay).
    std::error_code ignored;
    fs::remove(CheckpointPath(long_run.out), ignored);
    fs::remove(CheckpointPath(long_run.out).parent_path(), ignored);
  }
  return summary;
}

}  // namespace owval::engine
