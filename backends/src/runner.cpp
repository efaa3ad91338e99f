#include "owval/backends/runner.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "owval/backends/process.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/command_template.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/json_file.hpp"
#include "owval/engine/config.hpp"
#include "owval/engine/run.hpp"
#include "owval/trajectory/formats.hpp"
#include "owval/trajectory/writer.hpp"

namespace owval::backends {
namespace fs = std::filesystem;

namespace {

TemplateValues ValuesFor(const Backend& b, const RunRequest& r, const std::string& config,
                         const std::string& out) {
  TemplateValues v;
  v.values = {{"config", config},
              {"time", FormatNumber(r.scenario.time_s, 17)},
              {"time_step", FormatNumber(r.scenario.time_step_s, 17)},
              {"log_step", std::to_string(r.scenario.log_step)},
              {"out", out}};
  v.sets = b.set_defaults;
  for (const auto& [k, value] : r.sets) v.sets[k] = value;
  return v;
}

// How a backend's output in `layout` ("hdf5", or a text layout) is read, quietly.
TextReadOptions Reading(const std::string& layout) {
  TextReadOptions options;
  options.layout = layout == "hdf5" ? TextLayout::kAuto : ParseLayout(layout);
  options.quiet = true;
  return options;
}

// Every frame of a backend's output read once, with every check a whole read makes (InputError
// naming the file otherwise), one frame in memory at a time.
void CheckOutput(const fs::path& file, const std::string& layout) {
  if (layout == "hdf5" && DetectFormat(file) != FileFormat::kHdf5)
    throw InputError(file.string(), 0, "expected an owval HDF5 file (layout hdf5)");
  const std::unique_ptr<FrameSource> frames = OpenFrameSource(file, Reading(layout));
  for (std::size_t f = 0; f < frames->frame_count(); ++f) frames->Frame(f);
}

// "backend NAME: what (stderr: tail)", clamped to 300 printable characters.
InputError BackendError(const std::string& name, std::string what, const fs::path& stderr_file) {
  const std::string tail = LogTail(stderr_file, 5, 150);
  const std::string suffix = tail.empty() ? " (stderr empty)" : " (stderr: " + tail + ")";
  const std::size_t room = 300 - std::min<std::size_t>(300, 10 + name.size() + suffix.size());
  if (what.size() > room) what = what.substr(0, room > 3 ? room - 3 : 0) + "...";
  for (char& c : what)
    if (c < 32 || c > 126) c = '?';
  return InputError("backend " + name + ": " + what + suffix);
}

// The engine's frames appended to Sibernetic text as they come (WriteSiberneticText's bytes):
// memory O(particles), whatever the run's length.
class TextSink : public engine::FrameSink {
 public:
  explicit TextSink(fs::path destination) : destination_(std::move(destination)) {}
  void Begin(const Trajectory& h, int /*threads*/) override {
    writer_ = OpenTrajectoryWriter(destination_, {h.box, h.time_step_s, h.log_step, h.type, {}});
  }
  void Frame(const engine::FrameView& f) override {
    writer_->AppendFrame(f.time_s, f.positions.data());
  }
  void Close() { writer_->Close(); }

 private:
  fs::path destination_;
  std::unique_ptr<TrajectoryWriter> writer_;
};

// The engine in process; the trajectory is written as Sibernetic text (6 digits, as a command
// backend's would be) so that a fresh run and a cache hit read the same numbers.
void RunBuiltin(const Backend& b, const RunRequest& r, const fs::path& dir) {
  const engine::SiberneticConfig config = engine::ReadSiberneticConfig(r.scenario.configuration);
  engine::RunOptions options;
  options.duration_s = r.scenario.time_s;
  options.log_step = r.scenario.log_step;
  options.backend = b.engine_backend;
  options.record_fields = false;
  if (r.scenario.time_step_s != options.constants.time_step_s)
    options.constants.time_step_s = r.scenario.time_step_s;
  TextSink text(dir / "position_buffer.txt");
  engine::Run(config, options, &text);
  text.Close();
}

fs::path RunCommand(const Backend& b, const RunRequest& r, const fs::path& dir) {
  // Absolute: the command runs in its working directory, and a relative --cache would otherwise
  // name another folder there (and a file written into {out} would not be recognised as such).
  const fs::path out = fs::absolute(dir / "out");
  fs::create_directories(out);
  const fs::path config = fs::absolute(r.scenario.configuration);
  ProcessOptions p;
  p.command = ExpandTemplate(b.command, ValuesFor(b, r, config.string(), out.string()), true,
                             "backend " + b.name + ": command");
  p.working_directory = b.working_directory;
  p.stdout_path = dir / "stdout.txt";
  p.stderr_path = dir / "stderr.txt";
  const ProcessResult result = RunShellCommand(p);
  if (!result.ok())
    throw BackendError(b.name, "command failed, " + result.Describe(), p.stderr_path);
  fs::path file = ExpandTemplate(b.output, ValuesFor(b, r, config.string(), out.string()), false,
                                 "backend " + b.name + ": output");
  if (file.is_relative())
    file = (b.working_directory.empty() ? fs::current_path() : b.working_directory) / file;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) == 0)
    throw BackendError(b.name, "command wrote nothing at " + file.string(), p.stderr_path);
  try {
    CheckOutput(file, b.layout);
  } catch (const InputError& e) {
    throw BackendError(b.name, std::string("unreadable output: ") + e.what(), p.stderr_path);
  }
  if (!fs::equivalent(file.parent_path(), out, ec)) fs::copy_file(file, out / file.filename());
  return fs::path("out") / file.filename();
}

RunOutcome Outcome(const std::string& source, const std::string& detail, const fs::path& file) {
  RunOutcome o;
  o.source = source;
  o.detail = detail;
  o.file = fs::absolute(file);  // read later, maybe from another working directory
  return o;
}

std::string ExecutableIdentity() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "unknown";
  const auto size = fs::file_size(exe, ec);
  const auto time = fs::last_write_time(exe, ec).time_since_epoch().count();
  return exe.string() + " " + std::to_string(size) + " " + std::to_string(time);
}

RunOutcome ReadStore(const Backend& b, const RunRequest& r, const std::string& why) {
  const fs::path dir = b.store / r.scenario.name;
  const fs::path file = RecordedTrajectory(dir);
  if (file.empty())
    throw InputError("backend " + b.name + ": store " + b.store.string() + " has no run of " +
                     r.scenario.name + " (no position_buffer.txt[.gz] or trajectory.h5)");
  RunOutcome o = Outcome("store", why + file.string(), file);
  o.reading = Reading(b.kind == BackendKind::kStore ? "auto" : b.layout);
  return o;
}

}  // namespace

std::unique_ptr<FrameSource> RunOutcome::Frames() const { return OpenFrameSource(file, reading); }

std::string ResolvedCommand(const Backend& b, const RunRequest& r, const fs::path& out_dir) {
  return ExpandTemplate(
      b.command, ValuesFor(b, r, fs::absolute(r.scenario.configuration).string(), out_dir.string()),
      true, "backend " + b.name + ": command");
}

std::string CacheKeyOf(const Backend& b, const RunRequest& r) {
  std::string producer;
  if (b.kind == BackendKind::kBuiltin) {
    producer = "built-in engine " + b.engine_backend + " of " + ExecutableIdentity();
  } else {
    TemplateValues v = ValuesFor(b, r, "{config}", "{out}");
    producer = "command " + ExpandTemplate(b.command, v, true, "backend " + b.name) + " in " +
               b.working_directory.string() + " output " + b.output + " layout " + b.layout;
  }
  return RunKey(producer, ReadWholeFile(r.scenario.configuration), r.scenario.time_s,
                r.scenario.time_step_s, r.scenario.log_step);
}

bool ProgramAvailable(const Backend& b) {
  std::istringstream words(b.command);
  std::string program;
  words >> program;
  std::error_code ec;
  if (program.find('/') != std::string::npos) {
    fs::path p = program;
    if (p.is_relative() && !b.working_directory.empty()) p = b.working_directory / p;
    return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
  }
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((fs::path(dir) / program).c_str(), X_OK) == 0) return true;
  return program == "cd" || program == "exec" || program == "env";  // shell built-ins we allow
}

RunOutcome ObtainRun(const Backend& b, const RunRequest& r, const RunCache& cache) {
  if (b.kind == BackendKind::kStore) return ReadStore(b, r, "");
  if (b.kind == BackendKind::kCommand && !b.store.empty() && !ProgramAvailable(b))
    return ReadStore(b, r, "fallback (command's program not found): ");
  if (r.scenario.configuration.empty())
    throw InputError(r.scenario.directory.string(), 0, "no configuration file to run");
  const std::string key = CacheKeyOf(b, r);
  const std::string layout = b.kind == BackendKind::kBuiltin ? "opencl" : b.layout;
  if (const auto hit = cache.Find(key)) {
    const nlohmann::json run = ReadJsonFile(*hit / "run.json");
    const fs::path file = *hit / run.at("output").get<std::string>();
    RunOutcome o = Outcome("cache hit", hit->string(), file);
    o.reading = Reading(layout);
    return o;
  }
  const fs::path temporary = cache.Begin(key);
  try {
    const auto start = std::chrono::steady_clock::now();
    fs::path output = "position_buffer.txt";
    if (b.kind == BackendKind::kBuiltin)
      RunBuiltin(b, r, temporary);
    else
      output = RunCommand(b, r, temporary);
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const nlohmann::json run = {{"backend", b.name},
                                {"output", output.string()},
                                {"scenario", r.scenario.name},
                                {"wall_s", wall_s}};
    WriteFileAtomically(temporary / "run.json", run.dump(2) + "\n");
    const fs::path dir = cache.Commit(temporary, key);
    RunOutcome o = Outcome("ran", cache.enabled() ? dir.string() : "not cached", dir / output);
    o.wall_s = wall_s;
    o.reading = Reading(layout);
    if (!cache.enabled())  // the file is read after this returns: removed with the last outcome
      o.uncached_directory =
          std::shared_ptr<const fs::path>(new fs::path(dir), [](const fs::path* d) {
            std::error_code ec;
            fs::remove_all(*d, ec);
            delete d;
          });
    return o;
  } catch (...) {
    std::error_code ec;
    fs::remove_all(temporary, ec);
    throw;
  }
}

}  // namespace owval::backends
