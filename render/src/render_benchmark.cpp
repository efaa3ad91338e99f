#include "owval/render/render_benchmark.hpp"

#include <chrono>
#include <random>

#include "owval/base/temporary_directory.hpp"
#include "owval/render/render.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::render {
namespace {
namespace fs = std::filesystem;

// The first `frames` frames (or frame 0 repeated), so both cases render the same amount.
Trajectory Frames(const Trajectory& source, std::size_t frames) {
  Trajectory t = source;
  t.positions.clear();
  t.time_s.clear();
  t.velocities.clear();
  t.density.clear();
  t.pressure.clear();
  for (std::size_t f = 0; f < frames; ++f)
    t.AppendFrame(double(f) * 1e-3, source.position(std::min(f, source.frame_count() - 1), 0));
  return t;
}

Trajectory Synthetic(std::size_t particles) {
  Trajectory t;
  t.box = {0, 100, 0, 100, 0, 100};
  t.time_step_s = 2e-5;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 100);
  std::vector<float> frame;
  for (std::size_t i = 0; i < particles; ++i) {
    t.type.push_back(i % 3 == 0 ? 2.1f : i % 3 == 1 ? 1.1f : 3.0f);
    frame.insert(frame.end(), {u(rng), u(rng), u(rng)});
  }
  t.AppendFrame(0, frame.data());
  return t;
}

nlohmann::json Time(const Trajectory& t, bool side_by_side, std::size_t frames) {
  RenderOptions o;
  o.boundary = BoundaryMode::kShown;  // draw every particle
  o.quiet = true;
  // Its own directory (a fixed /tmp name was shared by two runs at once), removed however it ends.
  const TemporaryDirectory scratch("owval-bench-render");
  const fs::path out = scratch.path() / "render.mp4";
  const Trajectory clip = Frames(t, frames);
  const auto start = std::chrono::steady_clock::now();
  const VideoSummary s =
      side_by_side ? RenderSideBySide(clip, clip, o, out) : RenderVideo(clip, o, out);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fs::remove(out);
  return {{"panels", side_by_side ? 2 : 1},
          {"particles_per_panel", t.particle_count()},
          {"frames", s.frames},
          {"size", "1280x720"},
          {"wall_s", wall},
          {"fps", double(s.frames) / wall}};
}

}  // namespace

nlohmann::json RunRenderBenchmark(const RenderBenchmarkOptions& a) {
  nlohmann::json cases = nlohmann::json::array();
  const fs::path& demo1 = a.demo1_trajectory;
  std::error_code ec;
  if (!demo1.empty() && fs::exists(demo1, ec)) {
    TextReadOptions quiet;
    quiet.quiet = true;
    const Trajectory t = ReadTrajectory(demo1, quiet);
    cases.push_back({{"case", "demo1 one panel"}, {"result", Time(t, false, a.frames)}});
    cases.push_back({{"case", "demo1 side by side"}, {"result", Time(t, true, a.frames)}});
  }
  const Trajectory big = Synthetic(100000);
  cases.push_back({{"case", "100k synthetic one panel"}, {"result", Time(big, false, a.frames)}});
  cases.push_back({{"case", "100k synthetic side by side"}, {"result", Time(big, true, a.frames)}});
  return {{"benchmark", "render"}, {"cases", cases}};
}

}  // namespace owval::render
