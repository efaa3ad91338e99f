#pragma once
// owval's own scenario generators. Each returns a configuration in Sibernetic's format
// (elastic particles first, then liquid, then the boundary walls) that ReadSiberneticConfig loads
// and WriteSiberneticConfig writes. Positions in configuration units (cu); r0 = 1.67 cu is the
// lattice spacing Sibernetic's own generators use (h / 2).
#include <cstddef>
#include <map>
#include <string>

#include "owval/engine/config.hpp"

namespace owval::scenarios {

using Parameters = std::map<std::string, double>;

struct WallOptions {
  // Lattice sites per axis; the box is [0, sites * r0] and wall particles sit at r0/2 + r0*k.
  int sites_x = 20, sites_y = 20, sites_z = 20;
  double r0_cu = 1.67;  // double, so that sites land on the nearest float to r0/2 + r0*k
  // 4th component of the wall normal (velocity slot). It enters Sibernetic's wall push
  // normalisation (physics sheet §3.8); the reference one_sprig file uses 3.
  float normal_w = 3.0f;
  // The generator behind Sibernetic's one_sprig_test dropped the x component of the normal on the
  // y-wall rows of the four edges parallel to z, leaving (0, ±0.707107, 0). Reproduce it to get a
  // file equivalent to the reference; otherwise edges get proper unit normals.
  bool reference_edge_normals = false;
};

// Appends the walls: the shell of the lattice, in the reference's row order (z walls over all x,y;
// then y walls over x and interior z; then x walls over interior y,z), with inward unit normals
// in the velocity slot. Sets the box. Returns the number of wall particles appended.
std::size_t AddBoxWalls(const WallOptions& options, engine::SiberneticConfig* config);

// Index of the wall particle nearest to (x, y, z) (cu). InputError if there is none within 1e-3.
std::size_t FindWallParticle(const engine::SiberneticConfig& config, float x, float y, float z);

// (a) One elastic particle (type 2.1) hanging by one spring from the top wall particle above the
// box centre. Defaults reproduce Sibernetic's configuration/test/one_sprig_test.
// Parameters: box_sites (20), r0_cu (1.67), rest_length_cu (14.195), start_y_cu (20.04),
// elastic_type (2.1), reference_edge_normals (1).
engine::SiberneticConfig OneSprig(const Parameters& parameters);

// (b) One liquid particle (type 1.1) falling from rest in the walled box.
// Parameters: box_sites (20), r0_cu (1.67), start_y_cu (25), reference_edge_normals (0).
engine::SiberneticConfig FreeFall(const Parameters& parameters);

// (c) A vertical chain of `beads` elastic particles hanging from the top wall particle above the
// box centre: bead 0 springs to the anchor, bead i to beads i-1 and i+1 (both directions listed,
// since Sibernetic's spring force acts only on the particle whose row lists it). Beads start at
// their rest lengths, so the chain sags and oscillates about its static equilibrium. The default
// spacing (4 cu) exceeds h = 3.34 cu so that no SPH force acts between beads: springs and gravity
// only. Parameters: box_sites (20), r0_cu (1.67), beads (5), spacing_cu (4), anchor_rest_length_cu
// (4), elastic_type (2.1: worm body, so bead-bead springs have full stiffness and the anchor
// spring 0.25), reference_edge_normals (0).
engine::SiberneticConfig HangingChain(const Parameters& parameters);

// (d) A liquid column (type 1.1) filling the box's whole floor (every interior lattice site in x
// and z) to `layers` layers, at rest: a hydrostatic column.
// Parameters: sites_xz (10), sites_y (16), r0_cu (1.67), layers (8), reference_edge_normals (0).
engine::SiberneticConfig LiquidColumn(const Parameters& parameters);

// (e) A still liquid block filling the floor of an open tank whose floor and four sides are
// `wall_layers` layers of boundary particles (the WCSPH scheme's dynamic boundary needs a kernel
// support of wall): the hydrostatic tank. Wall rows carry inward unit normals.
// Parameters: sites_x (12), sites_z (6), layers (24), r0_cu (1.67), wall_layers (3),
// headroom_layers (4).
engine::SiberneticConfig HydrostaticTank(const Parameters& parameters);

// (f) Martin & Moyce's (1952) dam break: a liquid column column_sites wide (a) and
// height_ratio x a high (n^2 = 2) against the left wall of a tank tank_sites long, released at
// rest. Walls as hydrostatic_tank's. Parameters: column_sites (16), height_ratio (2),
// tank_sites (80), sites_z (6), r0_cu (1.67), wall_layers (3), headroom_layers (4).
engine::SiberneticConfig DamBreak(const Parameters& parameters);

// Runs the generator named `generator` (one_sprig | free_fall | hanging_chain | liquid_column |
// hydrostatic_tank | dam_break).
engine::SiberneticConfig Generate(const std::string& generator, const Parameters& parameters);

}  // namespace owval::scenarios
