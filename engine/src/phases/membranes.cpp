#include "phases/membranes.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/kernels.hpp"

namespace owval::engine::internal {
namespace {

struct Vec3 {
  float x, y, z;
};

// a·b − c·d with the first product fused, as clang contracts it (sphFluid.cl:1074-1085).
float FusedDifference(float a, float b, float c, float d) { return Fma(a, b, -(c * d)); }

// Sum of the six triple products, each added or subtracted with one rounding
// (sphFluid.cl:1059-1060).
float Determinant(const Vec3& c1, const Vec3& c2, const Vec3& c3) {
  float d = Fma(c1.x * c2.y, c3.z, c1.y * c2.z * c3.x);
  d = Fma(c1.z * c2.x, c3.y, d);
  d = Fma(-(c1.z * c2.y), c3.x, d);
  d = Fma(-(c1.x * c2.z), c3.y, d);
  return Fma(-(c1.y * c2.x), c3.z, d);
}

// p·e in Sibernetic's order: (x + y) then + z, both additions fused.
float Dot3(const Vec3& p, const Vec3& e) { return Fma(p.z, e.z, Fma(p.x, e.x, p.y * e.y)); }

// Projection of p onto the plane through a, b, c: the point m on the plane with (m − p)
// orthogonal to b − a and c − a, solved by Cramer's rule. False when the system is singular.
bool ProjectOntoPlane(const Float4& p, const Float4& a, const Float4& b, const Float4& c, Vec3* m) {
  const Vec3 ab{b.x - a.x, b.y - a.y, b.z - a.z}, ac{c.x - a.x, c.y - a.y, c.z - a.z};
  const Vec3 n{FusedDifference(ab.y, ac.z, ab.z, ac.y), FusedDifference(ab.z, ac.x, ab.x, ac.z),
               FusedDifference(ab.x, ac.y, ab.y, ac.x)};
  // Rows: n·m = n·a (on the plane), ab·m = ab·p, ac·m = ac·p. Stored by columns.
  const Vec3 col1{n.x, ab.x, ac.x}, col2{n.y, ab.y, ac.y}, col3{n.z, ab.z, ac.z};
  const Vec3 pa{a.x, a.y, a.z}, pp{p.x, p.y, p.z};
  const Vec3 rhs{Dot3(pa, n), Dot3(pp, ab), Dot3(pp, ac)};
  const float det = Determinant(col1, col2, col3);
  if (det == 0.0f) return false;
  *m = {Determinant(rhs, col2, col3) / det, Determinant(col1, rhs, col3) / det,
        Determinant(col1, col2, rhs) / det};
  return true;
}

// Unit normal of triangle m seen from x: (x − projection)/|x − projection|, or false when the
// triangle is degenerate or x lies on its plane.
bool UnitNormal(const ElasticMatter& matter, const ParticleState& s, int m, const Float4& x,
                Vec3* unit) {
  const auto& tri = matter.membranes[std::size_t(m)];
  Vec3 projection;
  if (!ProjectOntoPlane(x, s.position[tri[0]], s.position[tri[1]], s.position[tri[2]], &projection))
    return false;
  const Vec3 normal{x.x - projection.x, x.y - projection.y, x.z - projection.z};
  const float length = std::sqrt(Dot3(normal, normal));  // sphFluid.cl:1204-1206
  if (!(length > 0.0f)) return false;
  *unit = {normal.x / length, normal.y / length, normal.z / length};
  return true;
}

// One liquid particle's unit normals by triangle: a triangle is listed by each of its three
// vertices, so the same normal is asked for up to three times; it is computed once (the same
// operations, so the same floats). Open addressing over a table larger than 32·7 entries.
class UnitNormals {
 public:
  UnitNormals(const ElasticMatter& matter, const ParticleState& s, const Float4& x)
      : matter_(matter), s_(s), x_(x) {}
  bool Get(int m, Vec3* unit) {
    if (!initialised_) {
      std::fill(key_, key_ + kSize, -1);
      initialised_ = true;
    }
    int h = (m * 2654435761u) >> 24;  // top 8 bits: kSize = 256
    while (key_[h] >= 0 && key_[h] != m) h = (h + 1) & (kSize - 1);
    if (key_[h] != m) {
      key_[h] = m;
      ok_[h] = UnitNormal(matter_, s_, m, x_, &unit_[h]);
    }
    *unit = unit_[h];
    return ok_[h];
  }

 private:
  static constexpr int kSize = 256;
  static_assert(kSize > kSlots * kMembraneSlots);
  const ElasticMatter& matter_;
  const ParticleState& s_;
  const Float4 x_;
  bool initialised_ = false;
  int key_[kSize];
  bool ok_[kSize];
  Vec3 unit_[kSize];
};

// The unit normals of the triangles listed for elastic particle j, seen from x, averaged; false
// when a triangle is degenerate or x lies on its plane.
bool AveragedNormal(const ElasticMatter& matter, std::int32_t j, UnitNormals* normals,
                    Vec3* average, bool* any) {
  Vec3 sum{0, 0, 0};
  int triangles = 0;
  for (int t = 0; t < kMembraneSlots; ++t) {
    const int m = matter.membrane_index[std::size_t(j) * kMembraneSlots + t];
    if (m < 0) break;
    Vec3 unit;
    if (!normals->Get(m, &unit)) return false;
    sum = {sum.x + unit.x, sum.y + unit.y, sum.z + unit.z};
    ++triangles;
  }
  *any = triangles > 0;
  if (*any)
    *average = {sum.x / float(triangles), sum.y / float(triangles), sum.z / float(triangles)};
  return true;
}

// Liquid particle i's push out of the membranes near it, or zero.
Float4 MembraneCorrection(const SphConstants& k, const ElasticMatter& matter,
                          const ParticleState& s, std::int32_t i) {
  const Float4 xi = s.position[i];
  Vec3 normals[kSlots];
  float distances[kSlots];
  int found = 0;
  UnitNormals unit_normals(matter, s, xi);
  const Neighbour* slots = s.slots(i);
  for (int n = 0; n < kSlots && slots[n].index >= 0; ++n) {
    const std::int32_t j = slots[n].index;
    const Float4 xj = s.position[j];
    if (!IsElastic(xj.w)) continue;
    bool any = false;
    if (!AveragedNormal(matter, j, &unit_normals, &normals[found], &any)) return {};
    if (!any) continue;
    // Distance with z dropped and the type codes' difference kept (a slip in Sibernetic's port,
    // commit 839ee75; gotcha 16).
    const float dx = xi.x - xj.x, dy = xi.y - xj.y, dw = xi.w - xj.w;
    distances[found++] = std::sqrt(dx * dx + dy * dy + dw * dw);
  }
  Vec3 normal{0, 0, 0};
  float weight_sum = 0, weighted_depth = 0;
  for (int m = 0; m < found; ++m) {
    const float w = BoundaryWeight(k.r0_cu, distances[m]);
    normal = {Fma(normals[m].x, w, normal.x), Fma(normals[m].y, w, normal.y),
              Fma(normals[m].z, w, normal.z)};  // sphFluid.cl:1265-1267
    weight_sum += w;
    weighted_depth = Fma(w, k.r0_cu - distances[m], weighted_depth);
  }
  // OpenCL dot() with w = 0, unfused as PoCL's library computes it.
  float length = (normal.x * normal.x + normal.y * normal.y) + normal.z * normal.z;
  if (found == 0 || length == 0.0f) return {};
  length = std::sqrt(length);
  return {normal.x / length * weighted_depth / weight_sum,
          normal.y / length * weighted_depth / weight_sum,
          normal.z / length * weighted_depth / weight_sum, 0};
}

}  // namespace

void InteractWithMembranes(const SphConstants& k, const ElasticMatter& matter, ParticleState* state,
                           std::vector<Float4>* scratch, int threads) {
  ParticleState& s = *state;
  std::vector<Float4>& correction = *scratch;
  correction.resize(s.size());  // only moving particles' entries are written and read
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t n = 0; n < s.moving.size(); ++n) {
    const std::int32_t i = s.moving[n];
    correction[i] = IsLiquid(s.position[i].w) ? MembraneCorrection(k, matter, s, i) : Float4{};
  }
  for (std::int32_t i : s.moving) {
    s.position[i].x += correction[i].x;
    s.position[i].y += correction[i].y;
    s.position[i].z += correction[i].z;
  }
}

}  // namespace owval::engine::internal
