#pragma once
// Which per-lane vector paths the kernels take. A vector path computes, per lane, exactly the
// operations of its scalar twin in the same order (fused where the scalar code calls Fma), so
// both give the same floats; AVX-512 is used when the running CPU has it, else AVX2 with FMA
// where a kernel has an 8-lane path. Tests turn the vector
// paths off to check that claim bit for bit.
namespace owval::engine::internal {

// True when the running CPU has AVX-512F and the vector paths are not switched off.
bool UseAvx512();
// True when the running CPU has AVX2 and FMA but not AVX-512F (the 8-lane paths), and the vector
// paths are not switched off. At most one of UseAvx512 and UseAvx2 is true.
bool UseAvx2();
// Switches the vector paths off (true) or back to the CPU's choice (false). Not thread-safe:
// call between runs.
void ForceScalarPaths(bool scalar);
// Takes the 8-lane paths even on an AVX-512 CPU (false when the CPU has no AVX2 and FMA), so that
// tests check them on every machine; ForceScalarPaths(false) returns to the CPU's choice.
bool ForceAvx2Paths();

}  // namespace owval::engine::internal
