#include "kernels/simd.hpp"

namespace owval::engine::internal {
namespace {

bool CpuHasAvx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}

bool CpuHasAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

bool use_avx512 = CpuHasAvx512();
bool use_avx2 = !use_avx512 && CpuHasAvx2();

}  // namespace

bool UseAvx512() { return use_avx512; }
bool UseAvx2() { return use_avx2; }
void ForceScalarPaths(bool scalar) {
  use_avx512 = !scalar && CpuHasAvx512();
  use_avx2 = !scalar && !use_avx512 && CpuHasAvx2();
}
bool ForceAvx2Paths() {
  use_avx512 = false;
  use_avx2 = CpuHasAvx2();
  return use_avx2;
}

}  // namespace owval::engine::internal
