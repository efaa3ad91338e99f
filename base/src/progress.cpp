#include "owval/base/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace owval {
namespace {
bool g_quiet = false;
}

bool QuietMode() { return g_quiet; }
void SetQuietMode(bool quiet) { g_quiet = quiet; }

Progress::Progress(std::string label, std::size_t total, bool quiet)
    : label_(std::move(label)),
      total_(total),
      enabled_(!quiet && !g_quiet && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() { Finish(); }

void Progress::Update(std::size_t done, const std::string& detail) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100) && done != total_) return;
  last_draw_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (total_ > 0) {
    const double fraction = static_cast<double>(done) / static_cast<double>(total_);
    const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
    std::fprintf(stderr, "\r%s %zu/%zu (%.0f%%) %.1fs eta %.1fs %s\033[K", label_.c_str(), done,
                 total_, 100 * fraction, elapsed, eta, detail.c_str());
  } else {
    std::fprintf(stderr, "\r%s %zu %.1fs %s\033[K", label_.c_str(), done, elapsed, detail.c_str());
  }
  std::fflush(stderr);
}

void Progress::Finish() {
  if (!enabled_ || finished_) return;
  finished_ = true;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
}

}  // namespace owval
