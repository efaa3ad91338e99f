#pragma once
// The one fused multiply-add the kernels may use.
#include <cmath>

namespace owval::engine::internal {

// a·b + c rounded once. PoCL builds Sibernetic's kernels with clang's default for OpenCL C,
// fp-contract=on: within one expression a product feeding an addition becomes llvm.fmuladd, which
// the x86 back end emits as an FMA instruction. The kernels here call Fma exactly where that
// happens (the ~60 sites of sphFluid.cl) and nowhere else; the engine is compiled with
// -ffp-contract=off so the C++ compiler adds no fusions of its own.
inline float Fma(float a, float b, float c) { return std::fma(a, b, c); }

}  // namespace owval::engine::internal
