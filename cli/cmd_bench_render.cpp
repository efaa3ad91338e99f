// owval bench render: frames per second of one-panel and side-by-side rendering, encoding
// included, for demo1 (17,841 particles, all drawn) and a 100,000-particle synthetic frame.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/render/render.hpp"
#include "owval/trajectory/formats.hpp"

namespace owval::cli {
namespace {
namespace fs = std::filesystem;

struct BenchRenderArgs {
  std::size_t frames = 120;
  std::string json_out;
};

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
  render::RenderOptions o;
  o.boundary = render::BoundaryMode::kShown;  // draw every particle
  o.quiet = true;
  const fs::path out = fs::temp_directory_path() / "owval_bench_render.mp4";
  const Trajectory clip = Frames(t, frames);
  const auto start = std::chrono::steady_clock::now();
  const render::VideoSummary s = side_by_side ? render::RenderSideBySide(clip, clip, o, out)
                                              : render::RenderVideo(clip, o, out);
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

void RunBench(const BenchRenderArgs& a) {
  nlohmann::json cases = nlohmann::json::array();
  const fs::path demo1 = fs::path(OWVAL_SHARED_DIR) / "reference/demo1/position_buffer.txt";
  if (fs::exists(demo1)) {
    TextReadOptions quiet;
    quiet.quiet = true;
    const Trajectory t = ReadTrajectory(demo1, quiet);
    cases.push_back({{"case", "demo1 one panel"}, {"result", Time(t, false, a.frames)}});
    cases.push_back({{"case", "demo1 side by side"}, {"result", Time(t, true, a.frames)}});
  }
  const Trajectory big = Synthetic(100000);
  cases.push_back({{"case", "100k synthetic one panel"}, {"result", Time(big, false, a.frames)}});
  cases.push_back({{"case", "100k synthetic side by side"}, {"result", Time(big, true, a.frames)}});
  const nlohmann::json out = {{"benchmark", "render"}, {"cases", cases}};
  std::cout << out.dump(2) << "\n";
  if (!a.json_out.empty()) WriteFileAtomically(a.json_out, out.dump(2) + "\n");
}

void SetUp(CLI::App& app) {
  auto a = std::make_shared<BenchRenderArgs>();
  CLI::App* cmd =
      Bench(app).add_subcommand("render", "Render + H.264 encode frames per second (JSON)");
  cmd->add_option("--frames", a->frames, "Frames per case");
  cmd->add_option("--json-out", a->json_out, "Also write the JSON result here");
  cmd->callback([a] { RunBench(*a); });
}

const bool registered = RegisterCommand(&SetUp);

}  // namespace
}  // namespace owval::cli
