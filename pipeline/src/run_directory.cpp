#include "owval/pipeline/run_directory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "owval/base/atomic_output.hpp"
#include "owval/base/command_template.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/json_file.hpp"
#include "owval/base/progress.hpp"
#include "owval/engine/constants.hpp"
#include "owval/engine/long_run.hpp"
#include "owval/engine/muscles.hpp"
#include "owval/engine/solver.hpp"
#include "owval/kinematics/midline.hpp"
#include "owval/kinematics/muscle_log.hpp"
#include "owval/kinematics/worm_track.hpp"
#include "owval/scenarios/scenario.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/frame_source.hpp"
#include "owval/trajectory/worm_formats.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval::pipeline {
namespace {
namespace fs = std::filesystem;

// The files a run writes besides its trajectories, each only when it applies (a worm, muscles,
// an adaptive scheme), and the OME-Zarr store (--zarr).
constexpr const char* kSideFiles[] = {"worm_motion_log.txt", "worm.wcon",
                                      "muscles_activity_buffer.txt", "step_log.json"};
constexpr const char* kZarrStore = "trajectory.zarr";

// FNV-1a 64 of the configuration file's bytes: identifies the input in WCON provenance.
std::string ConfigurationHash(const std::string& source) {
  std::error_code ec;
  if (!fs::is_regular_file(source, ec)) return "";
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : ReadWholeFile(source)) h = (h ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

// The writers of the outputs computed from the run's frames: the OME-Zarr (--zarr), for a worm
// Sibernetic's worm_motion_log.txt and worm.wcon (the formats other OpenWorm tools read), and for
// a muscle-driven run Sibernetic's muscles_activity_buffer.txt, each under the group's temporary
// name.
struct FrameOutputs {
  std::unique_ptr<OmeZarrWriter> zarr;
  std::unique_ptr<kinematics::WormMotionLogWriter> motion_log;
  std::unique_ptr<kinematics::WormWconWriter> wcon;
  std::unique_ptr<kinematics::MuscleLogWriter> muscles;
  int log_step = 1;
  std::size_t frames = 0;

  void Append(const FrameRef& frame) {
    const Trajectory& t = frame.trajectory;
    if (zarr) zarr->AppendFrame(t.time_s[frame.frame], t.position(frame.frame, 0));
    if (motion_log) motion_log->Append(t, frame.frame);
    if (wcon) wcon->Append(t, frame.frame);
    // Frame f is iteration k = f·log_step's state, and the activations logged with it are the
    // ones computed after iteration k (engine's run loop): MuscleSimulation.run()'s call k.
    const double step = double(frames++) * double(log_step);
    if (muscles) muscles->Append(engine::MuscleSimulationSignal(step));
  }
};

nlohmann::json WconSettings(const RunRequest& r, const std::string& source) {
  return {{"configuration", source}, {"configuration_fnv1a64", ConfigurationHash(source)},
          {"backend", r.backend},    {"integrator", r.integrator},
          {"muscles", r.muscles},    {"log_step", r.log_step},
          {"time_s", r.time_s}};
}

// Worm outputs and OME-Zarr need every frame: the finished trajectory.h5 (still under its
// temporary name) is read back frame by frame, each frame handed to every writer, so memory holds
// one frame and one Zarr chunk whatever the run's length (and a resumed run's frames are all in
// the file).
std::vector<std::string> WriteFrameOutputs(const Trajectory& header, const RunRequest& r,
                                           const std::string& source, bool muscles_driven,
                                           OutputGroup* group) {
  if (!r.zarr && !kinematics::IsWorm(header) && !muscles_driven) return {};
  const fs::path out = r.out;
  TextReadOptions quiet;
  quiet.quiet = true;
  const std::unique_ptr<FrameSource> frames =
      OpenFrameSource(group->TemporaryOf(out / "trajectory.h5"), quiet);
  const Trajectory& file = frames->header();
  FrameOutputs writers;
  std::vector<std::string> written;
  if (r.zarr) {
    writers.zarr = std::make_unique<OmeZarrWriter>(group->Stage(out / kZarrStore), file);
    written.push_back((out / kZarrStore).string());
  }
  if (kinematics::IsWorm(file)) {
    writers.motion_log = std::make_unique<kinematics::WormMotionLogWriter>(
        group->Stage(out / "worm_motion_log.txt"), file);
    writers.wcon = std::make_unique<kinematics::WormWconWriter>(
        group->Stage(out / "worm.wcon"), file, WconSettings(r, source), OWVAL_VERSION);
    written.push_back((out / "worm_motion_log.txt").string());
    written.push_back((out / "worm.wcon").string());
  }
  if (muscles_driven) {
    writers.muscles = std::make_unique<kinematics::MuscleLogWriter>(
        group->Stage(out / "muscles_activity_buffer.txt"));
    writers.log_step = file.log_step;
    written.push_back((out / "muscles_activity_buffer.txt").string());
  }
  for (std::size_t f = 0; f < frames->frame_count(); ++f) writers.Append(frames->Frame(f));
  if (writers.zarr) writers.zarr->Commit();
  if (writers.motion_log) writers.motion_log->Commit();
  if (writers.wcon) writers.wcon->Commit();
  if (writers.muscles) writers.muscles->Commit();
  return written;
}

// An adaptive scheme's time steps, rollbacks and density variation, one entry per frame, written
// as the frames come (memory does not grow with the run) and renamed into place when it completes.
class StepLogStream {
 public:
  StepLogStream(fs::path path, std::string backend)
      : path_(std::move(path)), backend_(std::move(backend)) {}
  void Append(std::string_view entry) {
    if (!file_) {
      file_ = std::make_unique<AtomicOutput>(path_);
      file_->stream() << "{\"backend\": " << nlohmann::json(backend_).dump() << ", \"frames\": [\n";
    } else {
      file_->stream() << ",\n";
    }
    file_->stream() << entry;
  }
  // Hands the finished file to the run's outputs; its path when the run wrote one, else "".
  std::string FinishInto(OutputGroup* group) {
    if (!file_) return "";
    file_->stream() << "\n]}\n";
    group->Adopt(file_.get());
    return path_.string();
  }

 private:
  fs::path path_;
  std::string backend_;
  std::unique_ptr<AtomicOutput> file_;
};

// What the run streams to besides its files: the trajectory's header (for the worm outputs) and,
// with stability, the gate's monitor.
struct Observers {
  Trajectory header;
  std::unique_ptr<compare::StabilityMonitor> monitor;
  std::unique_ptr<StepLogStream> step_log;
};

engine::LongRunOptions Files(const RunRequest& r, const RunDirectoryOptions& o, Observers* seen) {
  engine::LongRunOptions files;
  files.out = r.out;
  files.resume = o.resume;
  // A configuration file by its absolute path: --resume may be given from another directory.
  RunRequest invocation = r;
  std::error_code error;
  if (fs::is_regular_file(r.config, error)) invocation.config = fs::absolute(r.config).string();
  files.invocation = invocation.ToJson().dump();
  files.on_begin = [seen, stability = o.stability](const Trajectory& t) {
    seen->header = t;
    if (stability)
      seen->monitor = std::make_unique<compare::StabilityMonitor>(
          t.box, t.type, compare::LongRunStabilityOptions());
  };
  files.on_frame = [seen](const engine::FrameView& f) {
    if (!f.step_log.empty()) seen->step_log->Append(f.step_log);
    if (!seen->monitor) return;
    seen->monitor->Observe(f.time_s, f.positions.data(),
                           f.velocities.empty() ? nullptr : f.velocities.data(),
                           f.density.empty() ? nullptr : f.density.data());
  };
  return files;
}

// Every file the run may write, checked before it starts: a directory the user put in the way
// is refused (exit 2), never replaced. The OME-Zarr store replaces only an owval store.
// The configuration is an input too: `owval run DIR/position_buffer.txt --out DIR` replaced it.
void CheckRunOutputs(const RunRequest& r) {
  const fs::path out = r.out;
  const auto check = [&r](const fs::path& output) {
    CheckOutputPath(output);
    CheckOutputIsNotAnInput(output, {r.config});
  };
  for (const fs::path& output : engine::LongRunOutputs(out)) check(output);
  for (const char* name : kSideFiles) check(out / name);
  if (r.zarr) CheckZarrOutput(out / kZarrStore);
}

// An earlier run's side files that this run does not write leave with its commit: a muscle log
// beside a `--muscles off` run's trajectory would be read as this run's (checklist item 3).
// A Zarr store goes only when owval wrote it. So do the partial trajectories of an abandoned
// interrupted run (its checkpoint removed to start afresh); a resumed run's writers remove
// their own once they have read them. So do earlier failed runs' state dumps.
void RetireEarlierOutputs(const fs::path& out, const std::vector<std::string>& written,
                          bool resumed, OutputGroup* group) {
  const auto wrote = [&written](const fs::path& path) {
    return std::find(written.begin(), written.end(), path.string()) != written.end();
  };
  for (const char* name : kSideFiles)
    if (!wrote(out / name)) group->Retire(out / name);
  if (!wrote(out / kZarrStore)) group->Retire(out / kZarrStore, IsOwvalZarrStore(out / kZarrStore));
  if (!resumed)
    for (const fs::path& output : engine::LongRunOutputs(out)) group->Retire(PartialPath(output));
  // An earlier failed run's state dump: this run completed, so the directory no longer holds a
  // failure to look into (and a dump beside a good trajectory reads as this run's).
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(out, ec))
    if (entry.is_regular_file(ec) && engine::IsStateDumpName(entry.path()))
      group->Retire(entry.path());
}

// `path` as one shell word, quoted only when it has to be (the hint is pasted as written).
std::string ShellWord(const std::string& path) {
  const bool plain = !path.empty() && path.find_first_not_of(
                                          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                          "0123456789_-./+,:@%") == std::string::npos;
  return plain ? path : ShellQuote(path);
}

}  // namespace

void WriteWormWcon(const Trajectory& t, const nlohmann::json& settings, const fs::path& path) {
  if (!kinematics::IsWorm(t)) throw InputError(kinematics::kNotAWorm);
  WormTrack track = kinematics::TrackFromTrajectory(t, settings);
  track.software_version = OWVAL_VERSION;
  WriteWcon(track, path);
}

namespace {

// Every frame of `frames` to `append`, in order.
template <typename Append>
void ForEachFrame(FrameSource& frames, Append append) {
  for (std::size_t f = 0; f < frames.frame_count(); ++f) append(frames.Frame(f));
}

void ConvertToWcon(FrameSource& frames, const fs::path& in, const fs::path& out) {
  const Trajectory& header = frames.header();
  if (!kinematics::IsWorm(header)) throw InputError(in.string(), 0, kinematics::kNotAWorm);
  nlohmann::json settings = {{"source", in.string()}};
  for (const char* key : {"producer", "configuration", "configuration_fnv1a64", "backend"})
    if (header.provenance.count(key)) settings[key] = header.provenance.at(key);
  kinematics::WormWconWriter wcon(out, header, settings, OWVAL_VERSION);
  ForEachFrame(frames, [&](const FrameRef& f) { wcon.Append(f.trajectory, f.frame); });
  wcon.Commit();
}

void ConvertToZarr(FrameSource& frames, const fs::path& out) {
  OmeZarrWriter zarr(out, frames.header());
  ForEachFrame(frames, [&](const FrameRef& f) {
    zarr.AppendFrame(f.trajectory.time_s[f.frame], f.trajectory.position(f.frame, 0));
  });
  zarr.Commit();
}

// Sibernetic text through the streaming writer: WriteSiberneticText's bytes.
void ConvertToText(FrameSource& frames, const fs::path& out, TextLayout layout) {
  const Trajectory& h = frames.header();
  TrajectoryWriterOptions options;
  options.layout = layout == TextLayout::kAuto ? TextLayout::kOpenCL : layout;
  const std::unique_ptr<TrajectoryWriter> text =
      OpenTrajectoryWriter(out, {h.box, h.time_step_s, h.log_step, h.type, h.provenance}, options);
  ForEachFrame(frames, [&](const FrameRef& f) {
    text->AppendFrame(f.trajectory.time_s[f.frame], f.trajectory.position(f.frame, 0));
  });
  text->Close();
}

}  // namespace

void ConvertTrajectoryFile(const fs::path& in, const TextReadOptions& read, const fs::path& out,
                           TextLayout text_layout, TextReadReport* report) {
  CheckTrajectoryOutput(out);          // before the input is read
  CheckOutputIsNotAnInput(out, {in});  // atomic, yet a no-op at best
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(in, read, report);
  // Sibernetic's text of no frame is a header no reader takes (frame 0 lists the walls).
  if (frames->frame_count() == 0) throw InputError(in.string(), 0, "holds no frame to convert");
  const std::string extension = out.extension().string();
  if (extension == ".wcon")
    ConvertToWcon(*frames, in, out);
  else if (extension == ".zarr")
    ConvertToZarr(*frames, out);
  else if (extension == ".h5" || extension == ".hdf5")
    WriteHdf5(*frames, out);
  else
    ConvertToText(*frames, out, text_layout);
}

nlohmann::json RunRequest::ToJson() const {
  return {{"config", config},
          {"time_s", time_s},
          {"log_step", log_step},
          {"backend", backend},
          {"integrator", integrator},
          {"muscles", muscles},
          {"set", set},
          {"apply_physical_parameters", apply_physical_parameters},
          {"no_fields", no_fields},
          {"zarr", zarr},
          {"checkpoint_every", checkpoint_every}};
}

namespace {

using Json = nlohmann::json;

// The checkpoint's recorded arguments are of the types ToJson wrote, checked before any get<>():
// a flipped byte in them printed nlohmann's "[json.exception.parse_error.101] ..." as the line,
// and a log_step of 1e30 would have reached get<int>() (a float cast out of range).
void CheckRecordedArguments(const Json& j, const std::string& file) {
  if (!j.is_object()) throw InputError(file, 0, "bad run arguments: expected a JSON object");
  const auto need = [&j, &file](const char* key, bool (*ok)(const Json&), const char* expected) {
    if (!j.contains(key) || !ok(j[key]))
      throw InputError(file, 0,
                       std::string("bad run arguments: \"") + key + "\": expected " + expected);
  };
  const auto text = [](const Json& v) { return v.is_string(); };
  const auto flag = [](const Json& v) { return v.is_boolean(); };
  for (const char* key : {"config", "backend", "integrator", "muscles"})
    need(key, text, "a string");
  for (const char* key : {"apply_physical_parameters", "no_fields", "zarr"})
    need(key, flag, "true or false");
  need(
      "time_s", [](const Json& v) { return v.is_number() && std::isfinite(v.get<double>()); },
      "a finite number");
  need(
      "log_step",
      [](const Json& v) {
        return v.is_number_unsigned() && v.get<std::uint64_t>() >= 1 &&
               v.get<std::uint64_t>() <= std::numeric_limits<int>::max();
      },
      "a whole number from 1 to 2^31-1");
  need(
      "checkpoint_every", [](const Json& v) { return v.is_number_unsigned(); },
      "a whole number >= 0");
  need(
      "set",
      [](const Json& v) {
        return v.is_array() &&
               std::all_of(v.begin(), v.end(), [](const Json& s) { return s.is_string(); });
      },
      "an array of strings");
}

}  // namespace

RunRequest RunRequest::FromCheckpoint(const std::string& out) {
  const std::string file = engine::CheckpointPath(out).string();
  const Json j = ParseJsonText(engine::ReadCheckpointInvocation(out), file + " (run arguments)");
  CheckRecordedArguments(j, file);
  RunRequest r;
  r.config = j["config"], r.time_s = j["time_s"], r.log_step = j["log_step"];
  r.backend = j["backend"], r.integrator = j["integrator"];
  r.muscles = j["muscles"], r.set = j["set"].get<std::vector<std::string>>();
  r.apply_physical_parameters = j["apply_physical_parameters"];
  r.no_fields = j["no_fields"], r.zarr = j["zarr"];
  r.checkpoint_every = j["checkpoint_every"];
  r.out = out;
  return r;
}

nlohmann::json RunDirectorySummary::ToJson(const std::string& configuration) const {
  nlohmann::json j = {{"configuration", configuration},
                      {"first_step", run.first_step},
                      {"steps", run.steps},
                      {"frames", run.frames},
                      {"wall_s", run.wall_s},
                      {"steps_per_s", run.steps_per_s},
                      {"backend", backend},
                      {"reference_equivalent", run.reference_equivalent},
                      {"muscles_driven", run.muscles_driven},
                      {"interrupted", run.interrupted},
                      {"outputs", outputs}};
  if (stability) j["stability"] = stability->ToJson();
  return j;
}

std::string RunDirectorySummary::ToText() const {
  char line[512];
  std::snprintf(line, sizeof line, "ran steps %zu to %zu in %.2f s (%.0f steps/s), %zu frames -> ",
                run.first_step, run.steps, run.wall_s, run.steps_per_s, run.frames);
  return (stability ? stability->ToTable() : "") + line + out + "\n";
}

std::string RunDirectorySummary::FailureLine() const {
  const std::string step = std::to_string(run.steps);
  if (run.interrupted && run.checkpointed)
    return "interrupted after step " + step + ": partial trajectory in " + out + ", checkpoint " +
           engine::CheckpointPath(out).string() + "; continue with: owval run --resume " +
           ShellWord(out);
  if (run.interrupted)
    return "interrupted after step " + step + ": partial trajectory in " + out + " (backend " +
           backend + " cannot checkpoint: no --resume)";
  return stability && !stability->pass() ? stability->FailureLine() : "";
}

int RunDirectorySummary::exit_code(int stop_signal) const {
  if (run.interrupted) return 128 + stop_signal;
  return stability && !stability->pass() ? kExitGateFailed : kExitPass;
}

engine::RunOptions EngineOptions(const RunRequest& r) {
  engine::RunOptions options;
  options.duration_s = r.time_s;
  options.log_step = r.log_step;
  options.integrator = engine::ParseIntegrator(r.integrator);
  options.apply_physical_parameters = r.apply_physical_parameters;
  options.muscle_signal = engine::ParseMuscleSignal(r.muscles);
  options.record_fields = !r.no_fields;
  options.backend = engine::CanonicalBackend(r.backend);  // unknown: exit 2 naming the known ones
  options.dump_dir = r.out;
  options.checkpoint_every = r.checkpoint_every;
  engine::SetConstantAssignments(&options.constants, r.set);
  return options;
}

void RunIntoDirectory(const engine::SiberneticConfig& config, const RunRequest& request,
                      const RunDirectoryOptions& o, RunDirectorySummary* summary) {
  CheckRunOutputs(request);
  engine::RunOptions options = EngineOptions(request);
  options.threads = o.threads;
  options.on_step = o.on_step;
  options.stop_requested = o.stop_requested;
  Observers seen;
  OutputGroup outputs;  // every file of the run appears together
  seen.step_log =
      std::make_unique<StepLogStream>(fs::path(request.out) / "step_log.json", options.backend);
  engine::LongRunOptions files = Files(request, o, &seen);
  files.outputs = &outputs;
  summary->run = engine::RunToFiles(config, options, files);
  summary->backend = options.backend;
  const bool interrupted = summary->run.interrupted;
  for (const fs::path& output : engine::LongRunOutputs(request.out))
    summary->outputs.push_back((interrupted ? PartialPath(output) : output).string());
  if (!interrupted) {
    for (const std::string& path : WriteFrameOutputs(seen.header, request, config.source,
                                                     summary->run.muscles_driven, &outputs))
      summary->outputs.push_back(path);
    if (const std::string path = seen.step_log->FinishInto(&outputs); !path.empty())
      summary->outputs.push_back(path);
    RetireEarlierOutputs(request.out, summary->outputs, o.resume, &outputs);
    outputs.Commit();
  }
  if (seen.monitor)
    summary->stability = std::make_unique<compare::StabilityReport>(seen.monitor->report());
  summary->out = request.out;
  summary->configuration = config.source;
}

RunDirectorySummary RunNamedIntoDirectory(const RunRequest& request, RunDirectoryOptions options,
                                          const fs::path& data_dir, bool quiet) {
  if (request.config.empty() || request.out.empty())
    throw InputError("owval run: give CONFIG and --out DIR, or --resume DIR");
  const engine::SiberneticConfig config = scenarios::ResolveConfig(request.config, data_dir);
  Progress progress("run", 0, quiet);
  options.on_step = [&progress](std::size_t done, std::size_t total) {
    if (done % 50 == 0 || done == total)
      progress.Update(done, "of " + std::to_string(total) + " steps");
  };
  RunDirectorySummary summary;
  RunIntoDirectory(config, request, options, &summary);
  progress.Finish();
  return summary;
}

}  // namespace owval::pipeline
