#pragma once
// The trajectory model: what every owval library reads and writes. Positions are in Sibernetic's
// configuration units (cu); metres = cu * simulation_scale (7.4e-6 m/cu by default). Velocities
// are m/s, density kg/m^3, pressure Pa, time s. Nothing else in owval parses or writes trajectory
// files: see formats.hpp.
#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace owval {

// Integer part of Sibernetic's particle type code (position.w): 1 liquid, 2 elastic, 3 boundary.
enum class ParticleKind { kLiquid = 1, kElastic = 2, kBoundary = 3 };

// The kind of a type code such as 2.1 (C truncation, as Sibernetic does).
ParticleKind KindOf(float type_code);
// Whether Sibernetic knows the code: 1.x liquid, 2.x elastic, 3.x boundary. Its kernels take
// (int)type and handle 1, 2 and 3 only; KindOf reads any other value as boundary, so readers
// refuse it first (the engine's configuration reader does the same, CheckTypeCode).
bool IsSiberneticTypeCode(float type_code);
// What a refused type code's message says was expected.
inline constexpr const char* kExpectedTypeCode =
    "expected a type 1.x (liquid), 2.x (elastic) or 3.x (boundary)";
const char* KindName(ParticleKind kind);

// Simulation box in configuration units.
struct Box {
  float xmin = 0, xmax = 0, ymin = 0, ymax = 0, zmin = 0, zmax = 0;
  float extent(int axis) const;
  float lower(int axis) const;
  float upper(int axis) const;
};

struct Trajectory {
  Box box;
  double time_step_s = 0;  // simulation step dt
  int log_step = 1;        // steps between frames
  // Per particle, in file order (elastic, liquid, boundary by convention): the full type code.
  std::vector<float> type;
  // Per frame: simulation time in seconds.
  std::vector<double> time_s;
  // [frame][particle][xyz], row-major, configuration units. Boundary particles are present in
  // every frame (copied from frame 0 when the source file omits them: they never move).
  std::vector<float> positions;
  // Optional, same shape as positions (m/s) or [frame][particle] (density, pressure); empty if
  // the source carries none.
  std::vector<float> velocities;
  std::vector<float> density;
  std::vector<float> pressure;
  // Provenance attributes (producer, version, scenario, parameters, source file hash, ...).
  std::map<std::string, std::string> provenance;

  std::size_t particle_count() const { return type.size(); }
  std::size_t frame_count() const { return time_s.size(); }
  std::size_t count(ParticleKind kind) const;

  const float* position(std::size_t frame, std::size_t particle) const {
    return &positions[(frame * particle_count() + particle) * 3];
  }
  float* position(std::size_t frame, std::size_t particle) {
    return &positions[(frame * particle_count() + particle) * 3];
  }
  float coordinate(std::size_t frame, std::size_t particle, int axis) const {
    return positions[(frame * particle_count() + particle) * 3 + axis];
  }
  bool has_velocities() const { return !velocities.empty(); }
  bool has_density() const { return !density.empty(); }
  bool has_pressure() const { return !pressure.empty(); }

  // Throws std::logic_error when array sizes disagree with particle and frame counts.
  void CheckShape() const;
  // Appends one frame (positions for every particle, size 3 * particle_count()).
  void AppendFrame(double time_s, const float* frame_positions);
};

// Frames are paired by time (PairFramesByTime), so a file whose frame times repeat or go back
// would pair a candidate's frames with the wrong reference frames. InputError naming `file`, the
// first frame whose time is not finite or not after its predecessor's, and both times, after
// `where` (the dataset or header the times come from); nothing otherwise.
void CheckFrameTimesIncrease(const std::vector<double>& time_s, const std::string& file,
                             const std::string& where = "");

// Particle indices of a group: "elastic", "liquid", "boundary", "all" (every non-boundary
// particle when moving_only) . Throws InputError for an unknown name.
std::vector<std::size_t> GroupIndices(const Trajectory& trajectory, const std::string& group);

// Centroid of the given particles at one frame.
std::array<double, 3> Centroid(const Trajectory& trajectory, std::size_t frame,
                               const std::vector<std::size_t>& particles);

// One coordinate over all frames: of a particle, or of a group centroid.
std::vector<double> ParticleSeries(const Trajectory& trajectory, std::size_t particle, int axis);
std::vector<double> CentroidSeries(const Trajectory& trajectory,
                                   const std::vector<std::size_t>& particles, int axis);

}  // namespace owval
