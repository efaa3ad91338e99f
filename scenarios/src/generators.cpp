#include <cmath>

#include "owval/base/errors.hpp"
#include "owval/scenarios/scenario.hpp"

namespace owval::scenarios {
namespace {

double Get(const std::map<std::string, double>& p, const std::string& key, double fallback) {
  const auto it = p.find(key);
  return it == p.end() ? fallback : it->second;
}

void CheckKnown(const std::map<std::string, double>& p, std::initializer_list<const char*> known,
                const char* generator) {
  for (const auto& [key, value] : p) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (!ok) throw InputError(std::string(generator) + ": unknown parameter '" + key + "'");
  }
}

// Inward normal component on one axis for a lattice index at the low or high face.
float Inward(int index, int last) { return index == 0 ? 1.0f : index == last ? -1.0f : 0.0f; }

void EmptyConnections(std::size_t elastic, engine::SiberneticConfig* c) {
  c->connection.assign(elastic * engine::kConnectionSlots, {-1, 0, 0, 0});
  c->particle_mem_index.assign(elastic * engine::kMembraneSlotsPerParticle, -1);
}

}  // namespace

void AddBoxWalls(float box_cu, float r0_cu, float normal_w, engine::SiberneticConfig* c) {
  const int n = static_cast<int>(std::lround(box_cu / r0_cu));
  if (n < 3) throw InputError("box walls: the box must be at least 3 particle spacings wide");
  c->box = {0, box_cu, 0, box_cu, 0, box_cu};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const float nx = Inward(i, n - 1), ny = Inward(j, n - 1), nz = Inward(k, n - 1);
        if (nx == 0 && ny == 0 && nz == 0) continue;  // interior: not a wall
        const float length = std::sqrt(nx * nx + ny * ny + nz * nz);
        const float h = r0_cu / 2;
        c->position.push_back(
            {h + r0_cu * float(i), h + r0_cu * float(j), h + r0_cu * float(k), 3.0f});
        c->velocity.push_back({nx / length, ny / length, nz / length, normal_w});
      }
}

engine::SiberneticConfig OneSprig(const std::map<std::string, double>& p) {
  CheckKnown(p, {"box_cu", "rest_length_cu", "start_y_cu", "r0_cu"}, "one_sprig");
  const float box = float(Get(p, "box_cu", 33.4)), r0 = float(Get(p, "r0_cu", 1.67));
  engine::SiberneticConfig c;
  c.source = "owval generator one_sprig";
  const float centre = r0 / 2 + r0 * std::floor(box / r0 / 2);  // a lattice column at the middle
  c.position.push_back({centre, float(Get(p, "start_y_cu", 20.04)), centre, 2.1f});
  c.velocity.push_back({0, 0, 0, 0});
  AddBoxWalls(box, r0, 3.0f, &c);
  // The anchor: the top wall's particle above the elastic one.
  const float top = r0 / 2 + r0 * float(std::lround(box / r0) - 1);
  std::size_t anchor = 0;
  for (std::size_t i = 1; i < c.position.size(); ++i)
    if (std::abs(c.position[i][0] - centre) < 1e-3f && std::abs(c.position[i][1] - top) < 1e-3f &&
        std::abs(c.position[i][2] - centre) < 1e-3f)
      anchor = i;
  if (anchor == 0) throw InputError("one_sprig: no wall particle above the box centre");
  EmptyConnections(1, &c);
  c.connection[0] = {float(anchor) + 0.1f, float(Get(p, "rest_length_cu", 14.195)), 0, 0};
  return c;
}

engine::SiberneticConfig FreeFall(const std::map<std::string, double>& p) {
  CheckKnown(p, {"box_cu", "start_y_cu", "r0_cu"}, "free_fall");
  const float box = float(Get(p, "box_cu", 33.4)), r0 = float(Get(p, "r0_cu", 1.67));
  engine::SiberneticConfig c;
  c.source = "owval generator free_fall";
  const float centre = r0 / 2 + r0 * std::floor(box / r0 / 2);
  c.position.push_back({centre, float(Get(p, "start_y_cu", 25.0)), centre, 1.1f});
  c.velocity.push_back({0, 0, 0, 0});
  AddBoxWalls(box, r0, 3.0f, &c);
  return c;
}

}  // namespace owval::scenarios
