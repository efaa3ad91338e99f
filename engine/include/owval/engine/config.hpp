#pragma once
// Sibernetic's configuration format (design notes §3; sibernetic_physics.md §2):
//   optional [physical parameters]  lines "name: value" (parsed, never applied by the original)
//   [simulation box]                6 numbers: xmin xmax ymin ymax zmin zmax (cu)
//   [position] / [velocity]         rows "x y z type" (TAB-separated; short rows repeat the last
//   field) [connection]                    32 rows per elastic particle: partner rest_length_cu
//   muscle extra [membranes]                     rows "i j k" (elastic particle ids)
//   [particleMemIndex]              7 rows per elastic particle (-1 = none)
//   [end]
// Elastic particles come first; rows are in file order.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "owval/trajectory/trajectory.hpp"

namespace owval::engine {

inline constexpr int kConnectionSlots = 32;  // per elastic particle
inline constexpr int kMembraneSlotsPerParticle = 7;
inline constexpr int kNeighbourSlots = 32;

using Row4 = std::array<float, 4>;

struct SiberneticConfig {
  std::string source;  // file the configuration came from (for messages)
  Box box;
  std::vector<Row4> position;    // x, y, z (cu), type code
  std::vector<Row4> velocity;    // vx, vy, vz (m/s), 4th value; boundary rows: wall normal
  std::vector<Row4> connection;  // partner (float, -1 empty), rest length (cu), muscle id, extra
  std::vector<std::array<int, 3>> membranes;
  std::vector<int> particle_mem_index;  // kMembraneSlotsPerParticle per elastic particle
  // [physical parameters] as parsed with Sibernetic's rule (unsigned numbers; see physics sheet
  // §1).
  std::map<std::string, double> physical_parameters;

  std::size_t particle_count() const { return position.size(); }
  std::size_t elastic_count() const;
  std::size_t liquid_count() const;
  std::size_t boundary_count() const;
};

// Reads and validates a configuration. Throws InputError("file:line: ...") on malformed input,
// a missing [simulation box], position/velocity count mismatch, elastic particles not first,
// a connection block that is not 32 rows per elastic particle, a partner that does not exist,
// a membrane vertex that is not elastic, [membranes] without [particleMemIndex], a
// [particleMemIndex] value naming no membrane, an index no int holds, and a box whose neighbour
// grid (NeighbourGridCells with Sibernetic's default h) exceeds the memory budget: the sizes
// are checked before the engine allocates anything from them.
SiberneticConfig ReadSiberneticConfig(const std::filesystem::path& path);
SiberneticConfig ParseSiberneticConfig(const std::string& text, const std::string& name);

// Every filled [connection] slot as (elastic particle, partner), in file order: the elastic bonds,
// each listed from both ends as the file lists it.
std::vector<std::pair<std::uint32_t, std::uint32_t>> ConnectionPairs(
    const SiberneticConfig& config);

// Cells of the neighbour grid over `box` with cells of 2h (as the engine's NeighbourGrid counts
// them: from 0 to each maximum, two spare), saturating at SIZE_MAX.
std::size_t NeighbourGridCells(const Box& box, double h_cu);
// Bytes the grid keeps per cell (start offsets of static, moving and merged lists, and a count).
inline constexpr std::size_t kNeighbourGridBytesPerCell = 16;

// Writes a configuration Sibernetic itself can load (TAB-separated, [end] terminated), atomically.
void WriteSiberneticConfig(const SiberneticConfig& config, const std::filesystem::path& path);

// Sibernetic's defaults (inc/owPhysicsConstant.h), float values as its host code produces them.
// Each field is named, documented and checked in one table (owval/engine/constants.hpp).
struct PhysicsConstants {
  double mass_kg = 2.0e-12;
  double rest_density = 1000.0;  // rho0, kg/m^3
  double time_step_s = 2.0e-5;
  double simulation_scale = 7.39999905e-06;  // metres per configuration unit
  double h_cu = 3.34;                        // smoothing radius
  double r0_cu = 1.67;                       // h / 2
  double elasticity_coefficient = 3.0e8;     // 4 * 1.5e-4 / mass, s^-2
  double max_muscle_force = 4000.0;          // used as m/s^2
  std::array<double, 3> gravity = {0.0, -9.8, 0.0};
  int pcisph_iterations = 3;
  double delta = 0.178311437;             // PCISPH pressure scaling (fixed from default dt)
  double surface_tension_scale = 1.7e-9;  // coefficient in the cohesion term
  double viscosity = 4e-6;                // never used by Sibernetic's kernels
  double non_worm_body_spring_factor =
      0.25;  // sphFluid.cl: springs not between two worm-body particles

  // The XPBD scheme's parameters (engine/src/xpbd, docs/xpbd.md); PCISPH ignores them.
  struct Xpbd {
    int iterations = 1;  // constraint projection passes per substep (K)
    int substeps = 0;    // n substeps of dt/n per step [Macklin 2019]; 0: derived (docs/xpbd.md)
    double damping_budget = 0.02;  // derived n: amplitude lost per period by the stiffest bond
    int density_passes = 1;        // m density/wall corrections per step, bonds on every substep;
                             // 0: every constraint on every substep (the differentiable model's)
    double density_compliance = 0;     // alpha of C = rho/rho_rest - 1, s^2/cu^2; 0: derived
    double bond_compliance_scale = 1;  // alpha of a bond = scale / k_eff (k_eff in s^-2)
    double rest_density = 0;           // kg/m^3; 0: the configuration's interior liquid's
    double floor_restitution = 0;      // normal velocity kept (reversed) at the floor and walls
    double muscle_strength = 1;        // bond k(t) = k (1 + activation * strength)
    int viscosity = 1;                 // 1: add Sibernetic's viscosity force, 0: none
    int surface_tension = 1;           // 1: add Sibernetic's cohesion force, 0: none
    int pressure_force = 0;            // 1: add the SPH pressure-gradient force, 0: none
    int membranes = 0;         // 0: Sibernetic's membrane pass once per step (moves liquid only);
                               // 1: a liquid–triangle contact constraint in the projection passes
    int reciprocal_lists = 0;  // 1: keep a moving pair in the neighbour lists only when each
                               // particle lists the other (docs/xpbd.md); 0: Sibernetic's lists
    int body_push_only = 0;    // 1: in a liquid–elastic pair the elastic particle's density
                               // multiplier only pushes (docs/xpbd.md, item 10); 0: both ways
    // [MM13]'s artificial pressure s_corr = -k (W(r)/W(|dq|))^n in the density correction
    // (docs/xpbd.md): k (added to the pair's multipliers in units of h^2; 0: off), n, |dq|/h.
    double tensile_correction = 0;
    int tensile_exponent = 4;
    double tensile_distance_h = 0.2;
  } xpbd;

  // The WCSPH scheme's parameters (engine/src/wcsph, docs/wcsph.md); the other schemes ignore
  // them. Each technique of the scheme is a switch (1 on, 0 off).
  struct Wcsph {
    double h_factor = 1.2;             // h / particle spacing; the Wendland C2 support is 2h
    double spacing_m = 0;              // particle spacing; 0: the configuration's liquid's
    double sound_speed_factor = 10;    // c_s = max(factor sqrt(2 g H), c_min), H liquid height
    double min_sound_speed_m_s = 0;    // c_min
    double tait_gamma = 7;             // p = c_s^2 rho0/gamma ((rho/rho0)^gamma - 1)
    double cfl = 0.5;                  // dt_safe = cfl min(h/(c_s + |v|max), sqrt(h/|a|max))
    int density_diffusion = 1;         // delta-SPH (Molteni & Colagrossi 2009)
    double diffusion_delta = 0.1;      // its delta
    int xsph = 1;                      // XSPH velocity smoothing (Monaghan 1989)
    double xsph_epsilon = 0.5;         // its epsilon
    double viscosity_alpha = 0.01;     // Monaghan's artificial viscosity alpha (0: none)
    int optimistic_dt = 1;             // try factor dt_safe, roll back past the threshold
    double optimistic_factor = 1.5;    // the optimistic step's multiple of dt_safe
    double rollback_threshold = 0.03;  // max |rho - rho0|/rho0 that triggers a rollback
    int cooldown_steps = 10;           // steps at dt_safe after a rollback
    int morton_reorder = 1;            // reorder particles along a Morton curve of cells
    int reorder_interval = 20;         // steps between reorders
    int hydrostatic_start = 1;         // start densities from the hydrostatic Tait profile
  } wcsph;

  // A short description of where the constants differ from Sibernetic's defaults ("" if none);
  // scheme-specific parameters (xpbd, wcsph) are not listed.
  std::string DifferencesFromDefaults() const;
};

// Applies [physical parameters] to constants (what Sibernetic does NOT do), by the Sibernetic
// names of the constants' table. Returns the names applied; unknown names are returned in
// `ignored`; a value the table's rule refuses is an InputError naming the file and parameter.
std::vector<std::string> ApplyPhysicalParameters(const SiberneticConfig& config,
                                                 PhysicsConstants* constants,
                                                 std::vector<std::string>* ignored = nullptr);

}  // namespace owval::engine
