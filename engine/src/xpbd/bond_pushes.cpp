#include "xpbd/bond_pushes.hpp"

#include <immintrin.h>

#include <algorithm>
#include <numeric>

#include "kernels/point_lanes.hpp"

namespace owval::engine::internal {
namespace {

// LoadPoints for the points at points + offset[l], each offset three times the point's index:
// one indexed load a point, where LoadPoints' 3·index takes two more instructions.
__attribute__((target("avx2,fma"))) inline void LoadPointsAt(const float* points,
                                                             const std::int32_t* offset, __m256* x,
                                                             __m256* y, __m256* z) {
  const float* at[8];
  for (int l = 0; l < 8; ++l) at[l] = points + offset[l];
  LoadPoints(at, x, y, z);
}

// One group's rows, one per lane: each slot's push (λ updated unless `kKeepLambda` is false:
// a substep's only pass, whose λ nothing reads), summed slot by slot from +0. The pass's kind is
// a template parameter so that the slot loop carries no branch on it.
template <bool kFirstPass, bool kKeepLambda>
__attribute__((target("avx2,fma"))) inline void GroupPushesAvx2(
    const float* start, const std::int32_t* lane_offset, const std::int32_t* partner_offset,
    std::size_t first, std::size_t last, const float* rest_cu, const float* alpha_tilde,
    float* lambda, float sum[3][8]) {
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 sign = _mm256_set1_ps(-0.0f);
  __m256 ax, ay, az;
  LoadPointsAt(start, lane_offset, &ax, &ay, &az);
  __m256 sx = zero, sy = zero, sz = zero;
  for (std::size_t s = first; s < last; s += 8) {
    __m256 bx, by, bz;
    LoadPointsAt(start, partner_offset + s, &bx, &by, &bz);
    const __m256 dx = _mm256_sub_ps(ax, bx), dy = _mm256_sub_ps(ay, by), dz = _mm256_sub_ps(az, bz);
    // Norm: (d0·d0 + d1·d1) + d2·d2, each product rounded.
    const __m256 length = _mm256_sqrt_ps(_mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz)));
    const __m256 alpha = _mm256_loadu_ps(alpha_tilde + s);
    const __m256 rest = _mm256_loadu_ps(rest_cu + s);
    const __m256 old_lambda = kFirstPass ? zero : _mm256_loadu_ps(lambda + s);
    const __m256 taken = _mm256_and_ps(_mm256_cmp_ps(alpha, zero, _CMP_NLT_UQ),   // !(α̃ < 0)
                                       _mm256_cmp_ps(length, zero, _CMP_GT_OQ));  // L > 0
    const __m256 numerator = _mm256_sub_ps(_mm256_xor_ps(_mm256_sub_ps(length, rest), sign),
                                           _mm256_mul_ps(alpha, old_lambda));
    const __m256 dlambda = _mm256_div_ps(numerator, _mm256_add_ps(one, alpha));
    if constexpr (kKeepLambda)
      _mm256_storeu_ps(lambda + s,
                       _mm256_blendv_ps(old_lambda, _mm256_add_ps(old_lambda, dlambda), taken));
    const __m256 step = _mm256_div_ps(dlambda, length);
    sx = _mm256_add_ps(sx, _mm256_and_ps(taken, _mm256_mul_ps(step, dx)));
    sy = _mm256_add_ps(sy, _mm256_and_ps(taken, _mm256_mul_ps(step, dy)));
    sz = _mm256_add_ps(sz, _mm256_and_ps(taken, _mm256_mul_ps(step, dz)));
  }
  _mm256_storeu_ps(sum[0], sx);
  _mm256_storeu_ps(sum[1], sy);
  _mm256_storeu_ps(sum[2], sz);
}

// Pass's groups [first_group, last_group) in one function with the vector code, so that each
// group's sums go from registers straight to its particles' corrections.
struct Groups {
  const float* start;
  const std::int32_t *lane_particle, *lane_offset, *partner_offset;
  const std::size_t* group_slot;
  const float *rest_cu, *alpha_tilde;
  float* lambda;
};

template <bool kFirst, bool kKeepLambda>
__attribute__((target("avx2,fma"))) void PassGroupsAvx2(const Groups& in, Vec3<float>* p,
                                                        Vec3<float>* correction,
                                                        std::size_t first_group,
                                                        std::size_t last_group) {
  constexpr std::size_t kLanes = BondLanes::kLanes;
  for (std::size_t g = first_group; g < last_group; ++g) {
    float sum[3][kLanes];
    GroupPushesAvx2<kFirst, kKeepLambda>(in.start, &in.lane_offset[g * kLanes], in.partner_offset,
                                         in.group_slot[g], in.group_slot[g + 1], in.rest_cu,
                                         in.alpha_tilde, in.lambda, sum);
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::int32_t i = in.lane_particle[g * kLanes + l];
      if (i < 0) continue;
      if constexpr (kFirst) {
        correction[i] = {sum[0][l], sum[1][l], sum[2][l]};
      } else {
        for (int a = 0; a < 3; ++a) correction[i][a] = correction[i][a] + sum[a][l];
      }
      if (p != nullptr)
        for (int a = 0; a < 3; ++a) p[i][a] += sum[a][l];
    }
  }
}

}  // namespace

BondLanes::BondLanes(const std::vector<Bond>& bonds, const std::vector<std::size_t>& row_first,
                     std::size_t parts) {
  const std::size_t rows = row_first.empty() ? 0 : row_first.size() - 1;
  const std::size_t bond_count = rows == 0 ? 0 : row_first[rows] - row_first[0];
  parts = std::max<std::size_t>(1, parts);
  std::size_t r = 0;
  for (std::size_t t = 0; t < parts; ++t) {  // rows in order, cut at equal shares of the bonds
    part_group_.push_back(group_slot_.size());
    const std::size_t first = r;
    while (r < rows &&
           (t + 1 == parts || row_first[r] - row_first[0] < bond_count * (t + 1) / parts))
      ++r;
    std::vector<std::size_t> order(r - first);
    std::iota(order.begin(), order.end(), first);
    AddGroups(bonds, row_first, &order);
  }
  part_group_.push_back(group_slot_.size());
  group_slot_.push_back(slot_bond_.size());
  alpha_tilde_.assign(slot_bond_.size(), -1.0f);
  lambda_.assign(slot_bond_.size(), 0.0f);
  for (std::int32_t i : lane_particle_) lane_offset_.push_back(3 * std::max(0, i));
}

// Rows `order` (indices into row_first) as groups of eight, longest rows first.
void BondLanes::AddGroups(const std::vector<Bond>& bonds, const std::vector<std::size_t>& row_first,
                          std::vector<std::size_t>* rows_in) {
  std::vector<std::size_t>& order = *rows_in;
  const std::size_t rows = order.size();
  const auto length = [&](std::size_t r) { return row_first[r + 1] - row_first[r]; };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return length(a) > length(b); });
  for (std::size_t g = 0; g * kLanes < rows; ++g) {
    group_slot_.push_back(slot_bond_.size());
    const std::size_t slots = length(order[g * kLanes]);  // the group's longest row
    std::size_t lane_first[kLanes] = {}, lane_length[kLanes] = {};
    for (int l = 0; l < kLanes; ++l) {
      const std::size_t at = g * kLanes + std::size_t(l);
      lane_particle_.push_back(at < rows ? bonds[row_first[order[at]]].particle : -1);
      if (at < rows) lane_first[l] = row_first[order[at]], lane_length[l] = length(order[at]);
    }
    for (std::size_t k = 0; k < slots; ++k)
      for (int l = 0; l < kLanes; ++l) {
        const bool used = k < lane_length[l];
        const std::size_t b = lane_first[l] + k;
        slot_bond_.push_back(used ? std::int32_t(b) : -1);
        slot_partner_offset_.push_back(
            3 * (used ? bonds[b].partner : std::max(0, lane_particle_.back())));
        rest_cu_.push_back(used ? bonds[b].rest_cu : 0.0f);
      }
  }
}

void BondLanes::SetCompliance(const float* alpha_tilde) {
  for (std::size_t s = 0; s < slot_bond_.size(); ++s)
    alpha_tilde_[s] = slot_bond_[s] >= 0 ? alpha_tilde[slot_bond_[s]] : -1.0f;
}

void BondLanes::Pass(const Vec3<float>* start, Vec3<float>* p, Vec3<float>* correction, bool first,
                     std::size_t first_group, std::size_t last_group) {
  static_assert(sizeof(Vec3<float>) == 3 * sizeof(float), "points are three packed floats");
  const Groups in{
      start[0].data(),    lane_particle_.data(), lane_offset_.data(), slot_partner_offset_.data(),
      group_slot_.data(), rest_cu_.data(),       alpha_tilde_.data(), lambda_.data()};
  // A pass that is both a substep's first and its last (p null) keeps no λ: nothing reads it.
  if (first && p == nullptr)
    PassGroupsAvx2<true, false>(in, p, correction, first_group, last_group);
  else if (first)
    PassGroupsAvx2<true, true>(in, p, correction, first_group, last_group);
  else
    PassGroupsAvx2<false, true>(in, p, correction, first_group, last_group);
}

__attribute__((target("avx2,fma"))) void PredictAvx2(std::size_t values, float h, float to_cu,
                                                     const float* acceleration, float* v,
                                                     const float* x, float* p, float* p_copy) {
  const __m256 hv = _mm256_set1_ps(h), to_cu_v = _mm256_set1_ps(to_cu);
  std::size_t k = 0;
  for (; k + 8 <= values; k += 8) {
    const __m256 velocity =
        _mm256_add_ps(_mm256_loadu_ps(v + k), _mm256_mul_ps(hv, _mm256_loadu_ps(acceleration + k)));
    _mm256_storeu_ps(v + k, velocity);
    const __m256 position =
        _mm256_add_ps(_mm256_loadu_ps(x + k), _mm256_mul_ps(_mm256_mul_ps(hv, velocity), to_cu_v));
    _mm256_storeu_ps(p + k, position);
    _mm256_storeu_ps(p_copy + k, position);
  }
  for (; k < values; ++k) {
    v[k] += h * acceleration[k];
    p[k] = p_copy[k] = x[k] + h * v[k] * to_cu;
  }
}

// Eight values' velocity update from the bond correction and their position step, the
// rounding remainder carried (stored). One definition for both sweeps below, so that the update
// alone and the update fused with the next prediction round alike.
struct UpdatedLanes {
  __m256 velocity, position;
};
__attribute__((target("avx2,fma"))) inline UpdatedLanes UpdateLanes(__m256 hv, __m256 to_cu_v,
                                                                    __m256 scale_v,
                                                                    const float* correction,
                                                                    const float* v, const float* x,
                                                                    float* remainder) {
  const __m256 change = _mm256_div_ps(_mm256_mul_ps(_mm256_loadu_ps(correction), scale_v), hv);
  const __m256 velocity = _mm256_add_ps(_mm256_loadu_ps(v), change);
  const __m256 start = _mm256_loadu_ps(x);
  const __m256 move = _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(hv, velocity), to_cu_v),
                                    _mm256_loadu_ps(remainder));
  const __m256 position = _mm256_add_ps(start, move);
  _mm256_storeu_ps(remainder, _mm256_sub_ps(move, _mm256_sub_ps(position, start)));
  return {velocity, position};
}

__attribute__((target("avx2,fma"))) void UpdateVelocityAvx2(std::size_t values, float h,
                                                            float to_cu, float scale,
                                                            const float* correction, float* v,
                                                            float* x, float* p, float* remainder) {
  const __m256 hv = _mm256_set1_ps(h), to_cu_v = _mm256_set1_ps(to_cu),
               scale_v = _mm256_set1_ps(scale);
  std::size_t k = 0;
  for (; k + 8 <= values; k += 8) {
    const UpdatedLanes u =
        UpdateLanes(hv, to_cu_v, scale_v, correction + k, v + k, x + k, remainder + k);
    _mm256_storeu_ps(v + k, u.velocity);
    _mm256_storeu_ps(x + k, u.position);
    _mm256_storeu_ps(p + k, u.position);
  }
  for (; k < values; ++k) {
    v[k] = v[k] + correction[k] * scale / h;
    const float move = h * v[k] * to_cu + remainder[k];
    const float position = x[k] + move;
    remainder[k] = move - (position - x[k]);
    x[k] = p[k] = position;
  }
}

__attribute__((target("avx2,fma"))) void UpdateAndPredictAvx2(
    std::size_t values, float h, float to_cu, float scale, const float* correction,
    const float* acceleration, float* v, float* x, float* remainder, float* p_copy) {
  const __m256 hv = _mm256_set1_ps(h), to_cu_v = _mm256_set1_ps(to_cu),
               scale_v = _mm256_set1_ps(scale);
  std::size_t k = 0;
  for (; k + 8 <= values; k += 8) {
    const UpdatedLanes u =
        UpdateLanes(hv, to_cu_v, scale_v, correction + k, v + k, x + k, remainder + k);
    const __m256 position = u.position;
    _mm256_storeu_ps(x + k, position);
    const __m256 next_velocity =
        _mm256_add_ps(u.velocity, _mm256_mul_ps(hv, _mm256_loadu_ps(acceleration + k)));
    _mm256_storeu_ps(v + k, next_velocity);
    _mm256_storeu_ps(
        p_copy + k,
        _mm256_add_ps(position, _mm256_mul_ps(_mm256_mul_ps(hv, next_velocity), to_cu_v)));
  }
  for (; k < values; ++k) {
    v[k] = v[k] + correction[k] * scale / h;
    const float move = h * v[k] * to_cu + remainder[k];
    const float position = x[k] + move;
    remainder[k] = move - (position - x[k]);
    x[k] = position;
    v[k] += h * acceleration[k];
    p_copy[k] = x[k] + h * v[k] * to_cu;
  }
}

}  // namespace owval::engine::internal
