#include "owval/trajectory/io_benchmark.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/base/temporary_directory.hpp"
#include "owval/trajectory/frame_source.hpp"

namespace owval {
namespace {
namespace fs = std::filesystem;

// A demo1-like scene: a walled box of boundary particles and a block of moving particles whose
// positions wander, written in the OpenCL layout with Sibernetic's 6 significant digits.
constexpr int kSide = 40;  // the moving block's particles a side
constexpr std::size_t kMoving = kSide * kSide * kSide, kBoundary = 17498;

Trajectory SyntheticTrajectory(std::size_t frames) {
  Trajectory t;
  t.box = {0, 89.1f, 0, 89.1f, 0, 89.1f};
  t.time_step_s = 2e-5;
  t.log_step = 20;
  for (std::size_t i = 0; i < kMoving; ++i) t.type.push_back(i % 3 == 0 ? 2.1f : 1.1f);
  for (std::size_t i = 0; i < kBoundary; ++i) t.type.push_back(3.0f);
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f);
  std::vector<float> frame(t.type.size() * 3);
  for (std::size_t p = 0; p < t.type.size(); ++p)
    for (int a = 0; a < 3; ++a)
      frame[p * 3 + a] = 5.0f + 1.67f * static_cast<float>((p >> (4 * a)) % 45);
  for (std::size_t f = 0; f < frames; ++f) {
    for (std::size_t p = 0; p < kMoving * 3; ++p) frame[p] += jitter(rng);
    t.AppendFrame(static_cast<double>(f) * 20 * 2e-5, frame.data());
  }
  return t;
}

// The benchmark's generated files, removed however the benchmark ends (unless kept), SIGINT and
// SIGTERM included, with the directories that were missing for them (the writers' AtomicOutput
// creates those) when they are left empty.
class GeneratedFiles {
 public:
  GeneratedFiles(const fs::path& directory, bool keep)
      : missing_(directory), directory_(directory), keep_(keep) {
    if (keep) missing_.Keep();
  }
  GeneratedFiles(const GeneratedFiles&) = delete;
  GeneratedFiles& operator=(const GeneratedFiles&) = delete;
  fs::path Add(const std::string& name) {
    files_.push_back(std::make_unique<ScratchFile>(directory_ / name));
    if (keep_) files_.back()->Keep();
    return files_.back()->path();
  }

 private:
  MissingDirectories missing_;  // destroyed last: the folders once the files are gone
  fs::path directory_;
  bool keep_;
  std::vector<std::unique_ptr<ScratchFile>> files_;
};

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

nlohmann::json RunIoBenchmark(const IoBenchmarkOptions& a) {
  // ~27 bytes per row, a row per moving particle in every later frame. The generated trajectory
  // and the one read back are held in memory, 12 bytes a particle and frame: within the budget.
  if (!(a.text_size_mb > 0 && a.text_size_mb <= 1e9))
    throw InputError("--size-mb: expected a size above 0 and at most 1e9 MB, found " +
                     FormatNumber(a.text_size_mb, 6));
  // Checked before the text file is generated: libhdf5 refused a level of 99 only after it
  // ("HDF5: set deflate"), and took -1 or 0 frames a chunk.
  if (a.hdf5.compression_level < 0 || a.hdf5.compression_level > 9)
    throw InputError("--hdf5-level: expected a deflate level 0..9, found " +
                     std::to_string(a.hdf5.compression_level));
  if (a.hdf5.frames_per_chunk < 1)
    throw InputError("--hdf5-chunk-frames: expected 1 or more frames a chunk, found 0");
  const std::size_t frames =
      static_cast<std::size_t>(std::ceil(a.text_size_mb * 1e6 / (27.0 * double(kMoving))));
  CheckAllocation(SaturatingProduct(frames, (kMoving + kBoundary) * 12), "owval bench io",
                  "--size-mb");
  std::optional<TemporaryDirectory> scratch;
  fs::path directory = a.directory;
  if (directory.empty() && a.keep_files) directory = fs::temp_directory_path();
  if (directory.empty()) directory = scratch.emplace("owval-bench-io").path();
  GeneratedFiles generated(directory, a.keep_files);
  const fs::path text = generated.Add("owval_bench_position_buffer.txt");
  const fs::path h5 = generated.Add("owval_bench_trajectory.h5");
  {
    const Trajectory t = SyntheticTrajectory(frames);
    WriteSiberneticText(t, text, TextLayout::kOpenCL);
  }
  const double bytes = static_cast<double>(fs::file_size(text));
  TextReadOptions options;
  options.quiet = a.quiet;
  auto start = std::chrono::steady_clock::now();
  Trajectory t = ReadSiberneticText(text, options);
  const double parse_s = Seconds(start);
  start = std::chrono::steady_clock::now();
  WriteHdf5(t, h5, a.hdf5);
  const double write_s = Seconds(start);
  const double position_bytes = static_cast<double>(t.positions.size() * sizeof(float));
  t = Trajectory();
  start = std::chrono::steady_clock::now();
  const Trajectory back = ReadHdf5(h5);
  const double read_s = Seconds(start);
  // The same positions frame by frame, as compare, render and the checklist read a candidate.
  start = std::chrono::steady_clock::now();
  {
    const std::unique_ptr<FrameSource> stream = OpenFrameSource(h5);
    for (std::size_t f = 0; f < stream->frame_count(); ++f) stream->Frame(f);
  }
  const double stream_read_s = Seconds(start);
  nlohmann::json out = {
      {"benchmark", "io"},
      {"text_file_mb", bytes / 1e6},
      {"frames", back.frame_count()},
      {"particles", back.particle_count()},
      {"text_parse_s", parse_s},
      {"text_parse_mb_per_s", bytes / 1e6 / parse_s},
      {"hdf5_file_mb", static_cast<double>(fs::file_size(h5)) / 1e6},
      {"hdf5_write_s", write_s},
      {"hdf5_read_s", read_s},
      {"hdf5_read_gb_per_s_uncompressed", position_bytes / 1e9 / read_s},
      {"hdf5_stream_read_s", stream_read_s},
      {"hdf5_stream_read_gb_per_s_uncompressed", position_bytes / 1e9 / stream_read_s},
      {"hdf5_compression_level", a.hdf5.compression_level},
      {"hdf5_frames_per_chunk", a.hdf5.frames_per_chunk},
      {"threads", 1},  // text parsing
      {"hdf5_read_threads", omp_get_max_threads()},
  };
  return out;
}

}  // namespace owval
