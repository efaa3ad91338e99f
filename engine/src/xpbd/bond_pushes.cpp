#include "xpbd/bond_pushes.hpp"

#include <immintrin.h>

#include <algorithm>
#include <numeric>

namespace owval::engine::internal {
namespace {

// Per slot (eight lanes each): λ updated and the offsets d overwritten with the pushes.
__attribute__((target("avx2,fma"))) void PushesAvx2(std::size_t slots, const float* rest_cu,
                                                    const float* alpha_tilde, float* lambda,
                                                    float* dx_io, float* dy_io, float* dz_io) {
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 sign = _mm256_set1_ps(-0.0f);
  for (std::size_t s = 0; s < slots; s += 8) {
    const __m256 dx = _mm256_loadu_ps(dx_io + s), dy = _mm256_loadu_ps(dy_io + s),
                 dz = _mm256_loadu_ps(dz_io + s);
    // Norm: (d0·d0 + d1·d1) + d2·d2, each product rounded.
    const __m256 length = _mm256_sqrt_ps(_mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz)));
    const __m256 alpha = _mm256_loadu_ps(alpha_tilde + s);
    const __m256 rest = _mm256_loadu_ps(rest_cu + s);
    const __m256 old_lambda = _mm256_loadu_ps(lambda + s);
    const __m256 taken = _mm256_and_ps(_mm256_cmp_ps(alpha, zero, _CMP_NLT_UQ),   // !(α̃ < 0)
                                       _mm256_cmp_ps(length, zero, _CMP_GT_OQ));  // L > 0
    const __m256 numerator = _mm256_sub_ps(_mm256_xor_ps(_mm256_sub_ps(length, rest), sign),
                                           _mm256_mul_ps(alpha, old_lambda));
    const __m256 dlambda = _mm256_div_ps(numerator, _mm256_add_ps(one, alpha));
    _mm256_storeu_ps(lambda + s,
                     _mm256_blendv_ps(old_lambda, _mm256_add_ps(old_lambda, dlambda), taken));
    const __m256 step = _mm256_div_ps(dlambda, length);
    _mm256_storeu_ps(dx_io + s, _mm256_and_ps(taken, _mm256_mul_ps(step, dx)));
    _mm256_storeu_ps(dy_io + s, _mm256_and_ps(taken, _mm256_mul_ps(step, dy)));
    _mm256_storeu_ps(dz_io + s, _mm256_and_ps(taken, _mm256_mul_ps(step, dz)));
  }
}

// Per lane, the sum of slots [first, last) (eight lanes each) in slot order, from +0.
__attribute__((target("avx2,fma"))) void SumSlotsAvx2(const float* values, std::size_t first,
                                                      std::size_t last, float* sum) {
  __m256 total = _mm256_setzero_ps();
  for (std::size_t s = first; s < last; s += 8)
    total = _mm256_add_ps(total, _mm256_loadu_ps(values + s));
  _mm256_storeu_ps(sum, total);
}

}  // namespace

BondLanes::BondLanes(const std::vector<Bond>& bonds, const std::vector<std::size_t>& row_first) {
  const std::size_t rows = row_first.empty() ? 0 : row_first.size() - 1;
  std::vector<std::size_t> order(rows);
  std::iota(order.begin(), order.end(), 0);
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
        slot_partner_.push_back(used ? bonds[b].partner : std::max(0, lane_particle_.back()));
        rest_cu_.push_back(used ? bonds[b].rest_cu : 0.0f);
      }
  }
  group_slot_.push_back(slot_bond_.size());
  alpha_tilde_.assign(slot_bond_.size(), -1.0f);
  lambda_.assign(slot_bond_.size(), 0.0f);
  dx_.assign(slot_bond_.size(), 0.0f), dy_ = dx_, dz_ = dx_;
}

void BondLanes::SetCompliance(const float* alpha_tilde) {
  for (std::size_t s = 0; s < slot_bond_.size(); ++s)
    alpha_tilde_[s] = slot_bond_[s] >= 0 ? alpha_tilde[slot_bond_[s]] : -1.0f;
}

void BondLanes::ResetLambda() { std::fill(lambda_.begin(), lambda_.end(), 0.0f); }

void BondLanes::Pass(const Vec3<float>* start, Vec3<float>* p) {
  for (std::size_t g = 0; g + 1 < group_slot_.size(); ++g) {
    float ax[kLanes], ay[kLanes], az[kLanes];  // the lanes' own particles
    for (int l = 0; l < kLanes; ++l) {
      const Vec3<float>& a = start[std::max(0, lane_particle_[g * kLanes + std::size_t(l)])];
      ax[l] = a[0], ay[l] = a[1], az[l] = a[2];
    }
    for (std::size_t s = group_slot_[g]; s < group_slot_[g + 1]; s += kLanes)
      for (int l = 0; l < kLanes; ++l) {
        const Vec3<float>& b = start[slot_partner_[s + std::size_t(l)]];
        dx_[s + l] = ax[l] - b[0], dy_[s + l] = ay[l] - b[1], dz_[s + l] = az[l] - b[2];
      }
  }
  PushesAvx2(slot_bond_.size(), rest_cu_.data(), alpha_tilde_.data(), lambda_.data(), dx_.data(),
             dy_.data(), dz_.data());
  for (std::size_t g = 0; g + 1 < group_slot_.size(); ++g) {
    float sum[3][kLanes];
    SumSlotsAvx2(dx_.data(), group_slot_[g], group_slot_[g + 1], sum[0]);
    SumSlotsAvx2(dy_.data(), group_slot_[g], group_slot_[g + 1], sum[1]);
    SumSlotsAvx2(dz_.data(), group_slot_[g], group_slot_[g + 1], sum[2]);
    for (int l = 0; l < kLanes; ++l) {
      const std::int32_t i = lane_particle_[g * kLanes + std::size_t(l)];
      if (i < 0) continue;
      for (int a = 0; a < 3; ++a) p[i][a] += sum[a][l];
    }
  }
}

__attribute__((target("avx2,fma"))) void PredictAvx2(std::size_t values, float h, float to_cu,
                                                     const float* acceleration, float* v,
                                                     const float* x, float* p) {
  const __m256 hv = _mm256_set1_ps(h), to_cu_v = _mm256_set1_ps(to_cu);
  std::size_t k = 0;
  for (; k + 8 <= values; k += 8) {
    const __m256 velocity =
        _mm256_add_ps(_mm256_loadu_ps(v + k), _mm256_mul_ps(hv, _mm256_loadu_ps(acceleration + k)));
    _mm256_storeu_ps(v + k, velocity);
    _mm256_storeu_ps(p + k, _mm256_add_ps(_mm256_loadu_ps(x + k),
                                          _mm256_mul_ps(_mm256_mul_ps(hv, velocity), to_cu_v)));
  }
  for (; k < values; ++k) {
    v[k] += h * acceleration[k];
    p[k] = x[k] + h * v[k] * to_cu;
  }
}

__attribute__((target("avx2,fma"))) void UpdateVelocityAvx2(std::size_t values, float h,
                                                            float scale, float* v, float* x,
                                                            const float* p) {
  const __m256 hv = _mm256_set1_ps(h), scale_v = _mm256_set1_ps(scale);
  std::size_t k = 0;
  for (; k + 8 <= values; k += 8) {
    const __m256 position = _mm256_loadu_ps(p + k);
    _mm256_storeu_ps(
        v + k,
        _mm256_div_ps(_mm256_mul_ps(_mm256_sub_ps(position, _mm256_loadu_ps(x + k)), scale_v), hv));
    _mm256_storeu_ps(x + k, position);
  }
  for (; k < values; ++k) {
    v[k] = (p[k] - x[k]) * scale / h;
    x[k] = p[k];
  }
}

}  // namespace owval::engine::internal
