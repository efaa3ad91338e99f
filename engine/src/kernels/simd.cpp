#include "kernels/simd.hpp"

namespace owval::engine::internal {
namespace {

bool CpuHasAvx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}

bool use_avx512 = CpuHasAvx512();

}  // namespace

bool UseAvx512() { return use_avx512; }
void ForceScalarPaths(bool scalar) { use_avx512 = !scalar && CpuHasAvx512(); }

}  // namespace owval::engine::internal
