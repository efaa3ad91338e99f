// owval's scenario generators (see generators.hpp for the parameters and their defaults).
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>

#include "owval/base/errors.hpp"
#include "owval/base/format.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/scenarios/generators.hpp"

namespace owval::scenarios {
namespace {

using Defaults = std::initializer_list<std::pair<const char*, double>>;

// The parameters with defaults filled in; InputError for a name the generator does not know.
Parameters WithDefaults(const Parameters& given, Defaults defaults, const char* generator) {
  Parameters p;
  for (const auto& [name, value] : defaults) p[name] = value;
  for (const auto& [name, value] : given) {
    if (!p.count(name)) {
      std::string known;
      for (const auto& d : defaults) known += (known.empty() ? "" : ", ") + std::string(d.first);
      throw InputError(std::string(generator) + ": unknown parameter '" + name +
                       "' (known: " + known + ")");
    }
    p[name] = value;
  }
  return p;
}

int Count(const Parameters& p, const char* name, int minimum, const char* generator) {
  const double v = p.at(name);
  if (v != std::floor(v) || v < minimum || v > 100000)
    throw InputError(std::string(generator) + ": parameter '" + name +
                     "' must be a whole number >= " + std::to_string(minimum));
  return static_cast<int>(v);
}

// A length stored as a float: inf (and 1e300, infinite as a float) was written into the
// configuration as a spring's rest length.
float Positive(const Parameters& p, const char* name, const char* generator) {
  const double v = p.at(name);
  if (!(v > 0 && v <= std::numeric_limits<float>::max()))
    throw InputError(std::string(generator) + ": parameter '" + name +
                     "' must be a finite number > 0 (as a float, below 3.4e38)");
  return static_cast<float>(v);
}

// A switch: 0 or 1 (NaN, 0.5 and -1 were taken as "on").
bool Switch(const Parameters& p, const char* name, const char* generator) {
  const double v = p.at(name);
  if (v != 0 && v != 1)
    throw InputError(std::string(generator) + ": parameter '" + name + "' must be 0 or 1");
  return v == 1;
}

// The lattice spacing r0_cu, in (0, 2h]: 2h (6.68 cu with Sibernetic's h) is the neighbour
// grid's cell and beyond the kernels' reach, so particles of a sparser lattice never interact (and
// 1e30 made a box no grid can cover).
double Spacing(const Parameters& p, const char* generator) {
  const double v = p.at("r0_cu"), most = 2 * engine::PhysicsConstants{}.h_cu;
  if (!(v > 0 && v <= most))
    throw InputError(std::string(generator) + ": --param r0_cu=" + FormatNumber(v) +
                     " is not a lattice spacing in (0, " + FormatNumber(most) +
                     "] cu (2h, the kernels' reach)");
  return v;
}

// A height of the moving particle: inside the box [0, ymax] that `owval run` requires.
float HeightInBox(const Parameters& p, const char* name, double ymax, const char* generator) {
  const double v = p.at(name);
  if (!(v >= 0 && v <= ymax))
    throw InputError(std::string(generator) + ": --param " + name + "=" + FormatNumber(v) +
                     " puts the particle outside the simulation box (y from 0 to " +
                     FormatNumber(ymax) + " cu)");
  return float(v);
}

// The particles a lattice of sx x sy x sz sites can hold (walls and liquid take its sites), a
// position and a velocity each, checked against the memory budget before any is made:
// box_sites=100000 (6e10 wall particles) ran until the machine ran out of memory.
void CheckLatticeFits(int sx, int sy, int sz, const char* generator) {
  const std::size_t sites =
      SaturatingProduct(SaturatingProduct(std::size_t(sx), std::size_t(sy)), std::size_t(sz));
  CheckAllocation(SaturatingProduct(sites, 2 * sizeof(engine::Row4)), generator,
                  "a lattice of " + std::to_string(sx) + " x " + std::to_string(sy) + " x " +
                      std::to_string(sz) + " sites");
}

WallOptions CubicWalls(const Parameters& p, const char* generator) {
  WallOptions w;
  w.sites_x = w.sites_y = w.sites_z = Count(p, "box_sites", 3, generator);
  CheckLatticeFits(w.sites_x, w.sites_y, w.sites_z, generator);
  w.r0_cu = Spacing(p, generator);
  w.reference_edge_normals = Switch(p, "reference_edge_normals", generator);
  return w;
}

// Lattice coordinate of the site column at the middle of an axis of `sites` sites.
float Middle(const WallOptions& w, int sites) { return float(w.r0_cu / 2 + w.r0_cu * (sites / 2)); }
float TopWallY(const WallOptions& w) { return float(w.r0_cu / 2 + w.r0_cu * (w.sites_y - 1)); }

// Empty connection and membrane-index rows for `elastic` particles (partner -1 = empty slot).
void EmptyConnections(std::size_t elastic, engine::SiberneticConfig* c) {
  c->connection.assign(elastic * engine::kConnectionSlots, {-1, 0, 0, 0});
  c->particle_mem_index.assign(elastic * engine::kMembraneSlotsPerParticle, -1);
}

// Sibernetic stores the partner index as a float; the reference writes id + 0.1 so that
// truncation recovers the id whatever the float rounding.
float Partner(std::size_t index) { return float(index) + 0.1f; }

void AddParticle(engine::SiberneticConfig* c, float x, float y, float z, float type) {
  c->position.push_back({x, y, z, type});
  c->velocity.push_back({0, 0, 0, 0});
}

void CheckElasticType(float type, const char* generator) {
  if (KindOf(type) != ParticleKind::kElastic)
    throw InputError(std::string(generator) + ": elastic_type must be in [2, 3)");
}

}  // namespace

engine::SiberneticConfig OneSprig(const Parameters& given) {
  const Parameters p = WithDefaults(given,
                                    {{"box_sites", 20},
                                     {"r0_cu", 1.67},
                                     {"rest_length_cu", 14.195},
                                     {"start_y_cu", 20.04},
                                     {"elastic_type", 2.1},
                                     {"reference_edge_normals", 1}},
                                    "one_sprig");
  const WallOptions w = CubicWalls(p, "one_sprig");
  const float type = float(p.at("elastic_type"));
  CheckElasticType(type, "one_sprig");
  engine::SiberneticConfig c;
  c.source = "owval generator one_sprig";
  const float centre = Middle(w, w.sites_x);
  AddParticle(&c, centre, HeightInBox(p, "start_y_cu", w.r0_cu * w.sites_y, "one_sprig"), centre,
              type);
  AddBoxWalls(w, &c);
  const std::size_t anchor = FindWallParticle(c, centre, TopWallY(w), centre);
  EmptyConnections(1, &c);
  c.connection[0] = {Partner(anchor), Positive(p, "rest_length_cu", "one_sprig"), 0, 0};
  return c;
}

engine::SiberneticConfig FreeFall(const Parameters& given) {
  const Parameters p = WithDefaults(
      given,
      {{"box_sites", 20}, {"r0_cu", 1.67}, {"start_y_cu", 25}, {"reference_edge_normals", 0}},
      "free_fall");
  const WallOptions w = CubicWalls(p, "free_fall");
  engine::SiberneticConfig c;
  c.source = "owval generator free_fall";
  const float centre = Middle(w, w.sites_x);
  AddParticle(&c, centre, HeightInBox(p, "start_y_cu", w.r0_cu * w.sites_y, "free_fall"), centre,
              1.1f);
  AddBoxWalls(w, &c);
  return c;
}

engine::SiberneticConfig HangingChain(const Parameters& given) {
  const Parameters p = WithDefaults(given,
                                    {{"box_sites", 20},
                                     {"r0_cu", 1.67},
                                     {"beads", 5},
                                     {"spacing_cu", 4},
                                     {"anchor_rest_length_cu", 4},
                                     {"elastic_type", 2.1},
                                     {"reference_edge_normals", 0}},
                                    "hanging_chain");
  const WallOptions w = CubicWalls(p, "hanging_chain");
  const int beads = Count(p, "beads", 1, "hanging_chain");
  const float spacing = Positive(p, "spacing_cu", "hanging_chain");
  const float anchor_length = Positive(p, "anchor_rest_length_cu", "hanging_chain");
  const float type = float(p.at("elastic_type"));
  CheckElasticType(type, "hanging_chain");
  const float centre = Middle(w, w.sites_x), top = TopWallY(w);
  const float lowest = top - anchor_length - spacing * float(beads - 1);
  if (lowest <= float(w.r0_cu * 1.5))
    throw InputError("hanging_chain: the chain (lowest bead at y = " + std::to_string(lowest) +
                     " cu) does not fit above the floor; use fewer beads or a shorter spacing");
  engine::SiberneticConfig c;
  c.source = "owval generator hanging_chain";
  for (int b = 0; b < beads; ++b)
    AddParticle(&c, centre, top - anchor_length - spacing * float(b), centre, type);
  AddBoxWalls(w, &c);
  const std::size_t anchor = FindWallParticle(c, centre, top, centre);
  EmptyConnections(std::size_t(beads), &c);
  for (int b = 0; b < beads; ++b) {
    engine::Row4* rows = &c.connection[std::size_t(b) * engine::kConnectionSlots];
    int slot = 0;
    if (b == 0) rows[slot++] = {Partner(anchor), anchor_length, 0, 0};
    if (b > 0) rows[slot++] = {Partner(std::size_t(b - 1)), spacing, 0, 0};
    if (b + 1 < beads) rows[slot++] = {Partner(std::size_t(b + 1)), spacing, 0, 0};
  }
  return c;
}

engine::SiberneticConfig LiquidColumn(const Parameters& given) {
  const Parameters p = WithDefaults(given,
                                    {{"sites_xz", 10},
                                     {"sites_y", 16},
                                     {"r0_cu", 1.67},
                                     {"layers", 8},
                                     {"reference_edge_normals", 0}},
                                    "liquid_column");
  WallOptions w;
  w.sites_x = w.sites_z = Count(p, "sites_xz", 3, "liquid_column");
  w.sites_y = Count(p, "sites_y", 3, "liquid_column");
  CheckLatticeFits(w.sites_x, w.sites_y, w.sites_z, "liquid_column");
  w.r0_cu = Spacing(p, "liquid_column");
  w.reference_edge_normals = Switch(p, "reference_edge_normals", "liquid_column");
  const int layers = Count(p, "layers", 1, "liquid_column");
  if (layers > w.sites_y - 2)
    throw InputError("liquid_column: at most sites_y - 2 = " + std::to_string(w.sites_y - 2) +
                     " layers fit between floor and ceiling");
  engine::SiberneticConfig c;
  c.source = "owval generator liquid_column";
  const double half = w.r0_cu / 2;
  // Liquid on every interior site one spacing away from the walls: no gap for it to fall into.
  for (int j = 1; j <= layers; ++j)
    for (int i = 1; i < w.sites_x - 1; ++i)
      for (int k = 1; k < w.sites_z - 1; ++k)
        AddParticle(&c, float(half + w.r0_cu * i), float(half + w.r0_cu * j),
                    float(half + w.r0_cu * k), 1.1f);
  AddBoxWalls(w, &c);
  return c;
}

namespace {

// A tank of lattice sites: `wall_layers` layers of boundary particles under and around an
// interior of nx x nz sites, open above, `height` sites high in all. Every wall site carries its
// inward unit normal (the sum of the faces it lies behind). The box is the lattice's extent.
struct Tank {
  int nx, nz, height, wall_layers;
  double r0_cu;
  float Coordinate(int site) const { return float(r0_cu * (site + 0.5)); }
  // Lattice coordinate of interior site i (0-based) along an axis walled below.
  float Interior(int i) const { return Coordinate(wall_layers + i); }
};

void AddTank(const Tank& t, engine::SiberneticConfig* c) {
  const int sx = t.nx + 2 * t.wall_layers, sz = t.nz + 2 * t.wall_layers;
  for (int k = 0; k < sz; ++k)
    for (int j = 0; j < t.height; ++j)
      for (int i = 0; i < sx; ++i) {
        const int nx = i < t.wall_layers ? 1 : (i >= t.nx + t.wall_layers ? -1 : 0);
        const int ny = j < t.wall_layers ? 1 : 0;
        const int nz = k < t.wall_layers ? 1 : (k >= t.nz + t.wall_layers ? -1 : 0);
        if (nx == 0 && ny == 0 && nz == 0) continue;
        const float length = float(std::sqrt(double(nx * nx + ny * ny + nz * nz)));
        c->position.push_back({t.Coordinate(i), t.Coordinate(j), t.Coordinate(k), 3.0f});
        c->velocity.push_back({nx / length, ny / length, nz / length, 0.0f});
      }
  c->box = {0, float(t.r0_cu * sx), 0, float(t.r0_cu * t.height), 0, float(t.r0_cu * sz)};
}

// A block of liquid sites [0, nx) x [0, ny) x [0, nz) of the tank's interior, at rest.
void AddLiquidBlock(const Tank& t, int nx, int ny, int nz, engine::SiberneticConfig* c) {
  for (int j = 0; j < ny; ++j)
    for (int k = 0; k < nz; ++k)
      for (int i = 0; i < nx; ++i)
        AddParticle(c, t.Interior(i), t.Interior(j), t.Interior(k), 1.1f);
}

}  // namespace

engine::SiberneticConfig HydrostaticTank(const Parameters& given) {
  const char* name = "hydrostatic_tank";
  const Parameters p = WithDefaults(given,
                                    {{"sites_x", 12},
                                     {"sites_z", 6},
                                     {"layers", 24},
                                     {"r0_cu", 1.67},
                                     {"wall_layers", 3},
                                     {"headroom_layers", 4}},
                                    name);
  Spacing(p, name);
  const int layers = Count(p, "layers", 1, name), walls = Count(p, "wall_layers", 1, name);
  const Tank t{Count(p, "sites_x", 1, name), Count(p, "sites_z", 1, name),
               walls + layers + Count(p, "headroom_layers", 0, name), walls, p.at("r0_cu")};
  CheckLatticeFits(t.nx + 2 * t.wall_layers, t.height, t.nz + 2 * t.wall_layers, name);
  engine::SiberneticConfig c;
  c.source = "owval generator hydrostatic_tank";
  AddLiquidBlock(t, t.nx, layers, t.nz, &c);
  AddTank(t, &c);
  return c;
}

engine::SiberneticConfig DamBreak(const Parameters& given) {
  const char* name = "dam_break";
  const Parameters p = WithDefaults(given,
                                    {{"column_sites", 16},
                                     {"height_ratio", 2},
                                     {"tank_sites", 80},
                                     {"sites_z", 6},
                                     {"r0_cu", 1.67},
                                     {"wall_layers", 3},
                                     {"headroom_layers", 4}},
                                    name);
  Spacing(p, name);
  const int a = Count(p, "column_sites", 1, name), walls = Count(p, "wall_layers", 1, name);
  const double ratio = p.at("height_ratio");
  if (!(ratio > 0 && ratio <= 100)) throw InputError("dam_break: height_ratio must be in (0, 100]");
  const int column_height = std::max(1, int(std::lround(ratio * a)));
  const int length = Count(p, "tank_sites", a, name);
  const Tank t{length, Count(p, "sites_z", 1, name),
               walls + column_height + Count(p, "headroom_layers", 0, name), walls, p.at("r0_cu")};
  CheckLatticeFits(t.nx + 2 * t.wall_layers, t.height, t.nz + 2 * t.wall_layers, name);
  engine::SiberneticConfig c;
  c.source = "owval generator dam_break";
  AddLiquidBlock(t, a, column_height, t.nz, &c);
  AddTank(t, &c);
  return c;
}

engine::SiberneticConfig Generate(const std::string& generator, const Parameters& parameters) {
  if (generator == "hydrostatic_tank") return HydrostaticTank(parameters);
  if (generator == "dam_break") return DamBreak(parameters);
  if (generator == "one_sprig") return OneSprig(parameters);
  if (generator == "free_fall") return FreeFall(parameters);
  if (generator == "hanging_chain") return HangingChain(parameters);
  if (generator == "liquid_column") return LiquidColumn(parameters);
  throw InputError("unknown generator '" + generator +
                   "' (known: one_sprig, free_fall, hanging_chain, liquid_column, "
                   "hydrostatic_tank, dam_break)");
}

}  // namespace owval::scenarios
