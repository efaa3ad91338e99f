// Box walls as the shell of a lattice, in the row order of Sibernetic's one_sprig_test file.
#include <cmath>
#include <string>

#include "owval/base/errors.hpp"
#include "owval/scenarios/generators.hpp"

namespace owval::scenarios {
namespace {

// Inward normal component on one axis for lattice index `index` of `sites`.
float Inward(int index, int sites) { return index == 0 ? 1.0f : index == sites - 1 ? -1.0f : 0.0f; }

struct Site {
  int i, j, k;
};

void AppendWall(const WallOptions& o, Site s, bool y_wall_pass, engine::SiberneticConfig* c) {
  const double half = o.r0_cu / 2;
  c->position.push_back({float(half + o.r0_cu * s.i), float(half + o.r0_cu * s.j),
                         float(half + o.r0_cu * s.k), 3.0f});
  float nx = Inward(s.i, o.sites_x);
  const float ny = Inward(s.j, o.sites_y), nz = Inward(s.k, o.sites_z);
  const float length = std::sqrt(nx * nx + ny * ny + nz * nz);
  // The reference generator normalised these edge rows but never set their x component.
  if (o.reference_edge_normals && y_wall_pass) nx = 0;
  c->velocity.push_back({nx / length, ny / length, nz / length, o.normal_w});
}

}  // namespace

std::size_t AddBoxWalls(const WallOptions& o, engine::SiberneticConfig* c) {
  if (o.sites_x < 3 || o.sites_y < 3 || o.sites_z < 3)
    throw InputError("box walls: at least 3 lattice sites per axis are needed");
  if (!(o.r0_cu > 0)) throw InputError("box walls: r0_cu must be positive");
  c->box = {0, float(o.r0_cu * o.sites_x), 0, float(o.r0_cu * o.sites_y),
            0, float(o.r0_cu * o.sites_z)};
  const std::size_t before = c->position.size();
  const int last_x = o.sites_x - 1, last_y = o.sites_y - 1, last_z = o.sites_z - 1;
  for (int i = 0; i < o.sites_x; ++i)  // z walls: every (x, y)
    for (int j = 0; j < o.sites_y; ++j)
      for (int k : {0, last_z}) AppendWall(o, {i, j, k}, false, c);
  for (int i = 0; i < o.sites_x; ++i)  // y walls: every x, interior z
    for (int k = 1; k < last_z; ++k)
      for (int j : {0, last_y}) AppendWall(o, {i, j, k}, true, c);
  for (int j = 1; j < last_y; ++j)  // x walls: interior y and z
    for (int k = 1; k < last_z; ++k)
      for (int i : {0, last_x}) AppendWall(o, {i, j, k}, false, c);
  return c->position.size() - before;
}

std::size_t FindWallParticle(const engine::SiberneticConfig& c, float x, float y, float z) {
  for (std::size_t i = 0; i < c.position.size(); ++i) {
    const engine::Row4& p = c.position[i];
    if (KindOf(p[3]) == ParticleKind::kBoundary && std::abs(p[0] - x) < 1e-3f &&
        std::abs(p[1] - y) < 1e-3f && std::abs(p[2] - z) < 1e-3f)
      return i;
  }
  throw InputError("no wall particle at (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                   std::to_string(z) + ")");
}

}  // namespace owval::scenarios
