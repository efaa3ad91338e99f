#pragma once
// `owval bench render`: frames per second of one-panel and side-by-side rendering, H.264
// encoding included, for demo1 (17,841 particles, all drawn; when its reference run is present)
// and a 100,000-particle synthetic frame.
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace owval::render {

struct RenderBenchmarkOptions {
  std::size_t frames = 120;                // rendered per case
  std::filesystem::path demo1_trajectory;  // demo1's position_buffer.txt; skipped when absent
};

// {"benchmark": "render", "cases": [{"case": "demo1 one panel", "result": {"fps", ...}}, ...]}
nlohmann::json RunRenderBenchmark(const RenderBenchmarkOptions& options);

}  // namespace owval::render
