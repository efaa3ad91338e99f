#include "owval/kinematics/midline.hpp"

#include <cstdio>

#include "owval/base/atomic_output.hpp"

namespace owval::kinematics {

int MidlineBin(float t) {
  // Float arithmetic in Sibernetic's order; the 3e-7 nudges codes such as 2.1051 (stored as
  // 2.10509992) over the bin boundary.
  if (!(t > 2.05f && t < 2.25f)) return 0;
  const float base = t < 2.15f ? 2.1f : 2.2f;
  return static_cast<int>((t + 0.0000003f - base) * 10000.f) + 1;
}

bool IsWorm(const Trajectory& trajectory) {
  std::array<bool, kMidlineBins> seen{};
  for (float t : trajectory.type) {
    if (const int slot = PrintedBinSlot(t); slot >= 0) seen[slot] = true;
  }
  int bins = 0;
  for (bool s : seen) bins += s;
  return bins >= 10;
}

Midline ComputeMidline(const Trajectory& trajectory, std::size_t frame) {
  // Sibernetic keeps 200 float accumulators and a float counter per bin and only prints 51..149;
  // bins outside that range are summed there too but never shown, so they are skipped here.
  std::array<float, kMidlineBins> sx{}, sy{}, sz{}, n{};
  for (std::size_t i = 0; i < trajectory.particle_count(); ++i) {
    const int b = PrintedBinSlot(trajectory.type[i]);
    if (b < 0) continue;
    const float* p = trajectory.position(frame, i);
    sx[b] += p[0];
    sy[b] += p[1];
    sz[b] += p[2];
    n[b] += 1.f;
  }
  Midline m;
  for (int b = 0; b < kMidlineBins; ++b) {
    m.count[b] = static_cast<int>(n[b]);
    if (n[b] > 0) {
      sx[b] /= n[b];
      sy[b] /= n[b];
      sz[b] /= n[b];
    }
    m.x_mm[b] = sx[b] * kSiberneticSimulationScale * 1000.f;
    m.y_mm[b] = sy[b] * kSiberneticSimulationScale * 1000.f;
    m.z_mm[b] = sz[b] * kSiberneticSimulationScale * 1000.f;
  }
  return m;
}

namespace {

void AppendBlock(std::string* line, const char* label, const std::array<float, kMidlineBins>& v) {
  char buffer[32];
  *line += label;
  for (float value : v) {
    std::snprintf(buffer, sizeof buffer, "%e\t", static_cast<double>(value));
    *line += buffer;
  }
}

}  // namespace

std::string FormatWormMotionLine(const Midline& m, long step, double time_step_s) {
  char buffer[32];
  const float t_s = static_cast<float>(step) * static_cast<float>(time_step_s);
  std::snprintf(buffer, sizeof buffer, "%e", static_cast<double>(t_s));
  std::string line = buffer;
  AppendBlock(&line, "\tX:\t", m.z_mm);  // Sibernetic's axis swap, see midline.hpp
  AppendBlock(&line, "\tY:\t", m.x_mm);
  AppendBlock(&line, "\tZ:\t", m.y_mm);
  line += "\n";
  return line;
}

std::string WormMotionLog(const Trajectory& trajectory) {
  std::string log;
  for (std::size_t f = 0; f < trajectory.frame_count(); ++f) {
    const long step = static_cast<long>(f) * trajectory.log_step;
    log += FormatWormMotionLine(ComputeMidline(trajectory, f), step, trajectory.time_step_s);
  }
  return log;
}

void WriteWormMotionLog(const Trajectory& trajectory, const std::filesystem::path& path) {
  WormMotionLogWriter log(path, trajectory);
  for (std::size_t f = 0; f < trajectory.frame_count(); ++f) log.Append(trajectory, f);
  log.Commit();
}

WormMotionLogWriter::WormMotionLogWriter(const std::filesystem::path& path,
                                         const Trajectory& header)
    : out_(path), log_step_(header.log_step), time_step_s_(header.time_step_s) {
  out_.stream();  // an empty run still writes an (empty) file
}

void WormMotionLogWriter::Append(const Trajectory& trajectory, std::size_t frame) {
  const long step = static_cast<long>(frames_++) * log_step_;
  out_.stream() << FormatWormMotionLine(ComputeMidline(trajectory, frame), step, time_step_s_);
}

}  // namespace owval::kinematics
