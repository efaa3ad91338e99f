#include "phases/membranes.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cmath>

#include "kernels/kernels.hpp"
#include "kernels/point_lanes.hpp"
#include "kernels/simd.hpp"

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

// The same, for `count` triangles at once, eight per lane group: each lane does UnitNormal's
// operations in its order (fused where it calls Fma), so the floats are the scalar path's.
__attribute__((target("avx2,fma"))) void UnitNormalsAvx2(const ElasticMatter& matter,
                                                         const ParticleState& s, const int* tris,
                                                         int count, const Float4& x, Vec3* unit,
                                                         bool* ok) {
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const auto neg = [&](__m256 v) { return _mm256_xor_ps(v, sign); };
  const auto fma = [](__m256 a, __m256 b, __m256 c) { return _mm256_fmadd_ps(a, b, c); };
  const auto mul = [](__m256 a, __m256 b) { return _mm256_mul_ps(a, b); };
  const auto sub = [](__m256 a, __m256 b) { return _mm256_sub_ps(a, b); };
  const auto det3 = [&](const __m256* c1, const __m256* c2, const __m256* c3) {
    __m256 d = fma(mul(c1[0], c2[1]), c3[2], mul(mul(c1[1], c2[2]), c3[0]));
    d = fma(mul(c1[2], c2[0]), c3[1], d);
    d = fma(neg(mul(c1[2], c2[1])), c3[0], d);
    d = fma(neg(mul(c1[0], c2[2])), c3[1], d);
    return fma(neg(mul(c1[1], c2[0])), c3[2], d);
  };
  const auto dot3 = [&](const __m256* p, const __m256* e) {
    return fma(p[2], e[2], fma(p[0], e[0], mul(p[1], e[1])));
  };
  for (int first = 0; first < count; first += 8) {
    // Each corner's eight points by one 16-byte load per Float4 and a transpose: filling a stack
    // array lane by lane and reading it back as vectors stalled on store forwarding.
    const float* at[3][8];  // corner, lane
    for (int l = 0; l < 8; ++l) {
      const auto& tri = matter.membranes[std::size_t(tris[std::min(first + l, count - 1)])];
      for (int corner = 0; corner < 3; ++corner)
        at[corner][l] = &s.position[tri[std::size_t(corner)]].x;
    }
    __m256 v[3][3];  // corner, axis
    for (int corner = 0; corner < 3; ++corner)
      LoadPoints(at[corner], &v[corner][0], &v[corner][1], &v[corner][2]);
    __m256 a[3], ab[3], ac[3];
    for (int axis = 0; axis < 3; ++axis) {
      a[axis] = v[0][axis];
      ab[axis] = sub(v[1][axis], a[axis]);
      ac[axis] = sub(v[2][axis], a[axis]);
    }
    const __m256 n[3] = {fma(ab[1], ac[2], neg(mul(ab[2], ac[1]))),
                         fma(ab[2], ac[0], neg(mul(ab[0], ac[2]))),
                         fma(ab[0], ac[1], neg(mul(ab[1], ac[0])))};
    const __m256 p[3] = {_mm256_set1_ps(x.x), _mm256_set1_ps(x.y), _mm256_set1_ps(x.z)};
    const __m256 col1[3] = {n[0], ab[0], ac[0]}, col2[3] = {n[1], ab[1], ac[1]},
                 col3[3] = {n[2], ab[2], ac[2]};
    const __m256 rhs[3] = {dot3(a, n), dot3(p, ab), dot3(p, ac)};
    const __m256 det = det3(col1, col2, col3);
    const __m256 normal[3] = {sub(p[0], _mm256_div_ps(det3(rhs, col2, col3), det)),
                              sub(p[1], _mm256_div_ps(det3(col1, rhs, col3), det)),
                              sub(p[2], _mm256_div_ps(det3(col1, col2, rhs), det))};
    const __m256 length = _mm256_sqrt_ps(dot3(normal, normal));
    const int good =
        _mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(det, _mm256_setzero_ps(), _CMP_NEQ_OQ),
                                         _mm256_cmp_ps(length, _mm256_setzero_ps(), _CMP_GT_OQ)));
    alignas(32) float u[3][8];
    for (int axis = 0; axis < 3; ++axis)
      _mm256_store_ps(u[axis], _mm256_div_ps(normal[axis], length));
    for (int l = 0; l < 8 && first + l < count; ++l) {
      unit[first + l] = {u[0][l], u[1][l], u[2][l]};
      ok[first + l] = (good >> l) & 1;
    }
  }
}

// The triangles listed by liquid particle i's elastic neighbours, each listed once: a triangle is
// listed by each of its three vertices, and its normal seen from x_i is computed once (the same
// operations, so the same floats). `unique_of` is the calling thread's table of every triangle's
// place in this list, −1 where absent; it is −1 again everywhere once the list is destroyed.
// (An open-addressing hash cleared per particle took more instructions than the normals.)
class NeighbourTriangles {
 public:
  explicit NeighbourTriangles(int* unique_of) : unique_of_(unique_of) {}
  ~NeighbourTriangles() {
    for (int u = 0; u < unique_; ++u) unique_of_[triangle_[u]] = -1;
  }
  NeighbourTriangles(const NeighbourTriangles&) = delete;
  NeighbourTriangles& operator=(const NeighbourTriangles&) = delete;

  // Adds neighbour j's triangles; false when it lists none.
  bool AddNeighbour(const ElasticMatter& matter, std::int32_t j) {
    int listed = 0;
    for (int t = 0; t < kMembraneSlots; ++t) {
      const int m = matter.membrane_index[std::size_t(j) * kMembraneSlots + t];
      if (m < 0) break;
      uses_[used_ + listed++] = Unique(m);
    }
    if (listed == 0) return false;
    used_ += listed;
    first_use_[++neighbours_] = used_;
    return true;
  }
  // The unit normals of every unique triangle seen from x; false when one is degenerate or x lies
  // on its plane (then the particle's whole correction is cancelled, as Sibernetic's early return).
  bool ComputeNormals(const ElasticMatter& matter, const ParticleState& s, const Float4& x) {
    bool ok[kSize];
    if (unique_ >= 4 && (UseAvx2() || UseAvx512())) {
      UnitNormalsAvx2(matter, s, triangle_, unique_, x, unit_, ok);
    } else {
      for (int u = 0; u < unique_; ++u) ok[u] = UnitNormal(matter, s, triangle_[u], x, &unit_[u]);
    }
    return std::all_of(ok, ok + unique_, [](bool b) { return b; });
  }
  // Neighbour n's (in the order added) unit normals averaged, after ComputeNormals.
  Vec3 AveragedNormal(int n) const {
    Vec3 sum{0, 0, 0};
    const int listed = first_use_[n + 1] - first_use_[n];
    for (int t = 0; t < listed; ++t) {
      const Vec3& unit = unit_[uses_[first_use_[n] + t]];
      sum = {sum.x + unit.x, sum.y + unit.y, sum.z + unit.z};
    }
    return {sum.x / float(listed), sum.y / float(listed), sum.z / float(listed)};
  }

 private:
  static constexpr int kSize = 256;
  static_assert(kSize > kSlots * kMembraneSlots);
  int Unique(int m) {
    int& unique = unique_of_[m];
    if (unique < 0) {
      unique = unique_;
      triangle_[unique_++] = m;
    }
    return unique;
  }
  int triangle_[kSize];  // unique triangles, in first-listed order
  Vec3 unit_[kSize];
  int unique_ = 0;
  int uses_[kSlots * kMembraneSlots];  // per neighbour, its triangles' unique indices
  int first_use_[kSlots + 1] = {0};    // neighbour n's uses are [first_use_[n], first_use_[n + 1])
  int used_ = 0, neighbours_ = 0;
  int* unique_of_;
};

// Liquid particle i's push out of the membranes near it, or zero.
Float4 MembraneCorrection(const SphConstants& k, const ElasticMatter& matter,
                          const ParticleState& s, std::int32_t i, int* unique_of) {
  const Float4 xi = s.position[i];
  float distances[kSlots];
  int found = 0;
  NeighbourTriangles triangles(unique_of);
  const Neighbour* slots = s.slots(i);
  for (int n = 0; n < kSlots && slots[n].index >= 0; ++n) {
    const std::int32_t j = slots[n].index;
    const Float4 xj = s.position[j];
    if (!IsElastic(xj.w) || !triangles.AddNeighbour(matter, j)) continue;
    distances[found++] = MembraneDistance(xi, xj);
  }
  if (found == 0 || !triangles.ComputeNormals(matter, s, xi)) return {};
  Vec3 normal{0, 0, 0};
  float weight_sum = 0, weighted_depth = 0;
  for (int m = 0; m < found; ++m) {
    const Vec3 averaged = triangles.AveragedNormal(m);
    const float w = BoundaryWeight(k.r0_cu, distances[m]);
    normal = {Fma(averaged.x, w, normal.x), Fma(averaged.y, w, normal.y),
              Fma(averaged.z, w, normal.z)};  // sphFluid.cl:1265-1267
    weight_sum += w;
    weighted_depth = Fma(w, k.r0_cu - distances[m], weighted_depth);
  }
  // OpenCL dot() with w = 0, unfused as PoCL's library computes it.
  float length = (normal.x * normal.x + normal.y * normal.y) + normal.z * normal.z;
  if (length == 0.0f) return {};
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
#pragma omp parallel num_threads(threads)
  {
    std::vector<int> unique_of(matter.membranes.size(), -1);  // this thread's NeighbourTriangles
#pragma omp for schedule(static)
    for (std::size_t n = 0; n < s.moving.size(); ++n) {
      const std::int32_t i = s.moving[n];
      correction[i] = IsLiquid(s.position[i].w)
                          ? MembraneCorrection(k, matter, s, i, unique_of.data())
                          : Float4{};
    }
  }
  for (std::int32_t i : s.moving) {
    s.position[i].x += correction[i].x;
    s.position[i].y += correction[i].y;
    s.position[i].z += correction[i].z;
  }
}

}  // namespace owval::engine::internal
