#include <cstdio>

#include "owval/kinematics/kinematics.hpp"

namespace owval::kinematics {
namespace {

nlohmann::json Optional(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::string Line(const char* name, const std::optional<double>& v, const char* unit) {
  char buffer[128];
  if (v)
    std::snprintf(buffer, sizeof buffer, "%-26s %.4g %s\n", name, *v, unit);
  else
    std::snprintf(buffer, sizeof buffer, "%-26s none\n", name);
  return buffer;
}

}  // namespace

nlohmann::json Report::ToJson() const {
  return {{"frames", frames},
          {"duration_s", duration_s},
          {"length_mm", length_mm},
          {"midbody_speed_mm_per_s", Optional(midbody_speed_mm_s)},
          {"head_speed_mm_per_s", Optional(head_speed_mm_s)},
          {"tail_speed_mm_per_s", Optional(tail_speed_mm_s)},
          {"frequency_hz", Optional(frequency_hz)},
          {"fft_frequency_hz", Optional(fft_frequency_hz)},
          {"zero_crossing_frequency_hz", Optional(zero_crossing_frequency_hz)},
          {"frequency_note", frequency_note},
          {"wavelength_mm", Optional(wavelength_mm)},
          {"amplitude_mm", Optional(amplitude_mm)},
          {"max_amplitude_mm", Optional(max_amplitude_mm)},
          {"regime", RegimeName(regime)}};
}

std::string Report::ToText() const {
  char head[160];
  std::snprintf(head, sizeof head, "%zu frames over %.4g s, body length %.4g mm\n", frames,
                duration_s, length_mm);
  std::string s = head;
  s += Line("midbody speed", midbody_speed_mm_s, "mm/s (+ forward)");
  s += Line("head speed", head_speed_mm_s, "mm/s");
  s += Line("tail speed", tail_speed_mm_s, "mm/s");
  s += Line("bend frequency", frequency_hz, "Hz");
  if (!frequency_hz && !frequency_note.empty()) s += "  (" + frequency_note + ")\n";
  s += Line("  spectral peak", fft_frequency_hz, "Hz");
  s += Line("  zero crossings", zero_crossing_frequency_hz, "Hz");
  s += Line("wavelength", wavelength_mm, "mm");
  s += Line("amplitude", amplitude_mm, "mm");
  s += Line("max amplitude", max_amplitude_mm, "mm");
  s += std::string("regime                     ") + RegimeName(regime) + "\n";
  return s;
}

}  // namespace owval::kinematics
