#pragma once
// Which per-lane vector paths the kernels take. A vector path computes, per lane, exactly the
// operations of its scalar twin in the same order (fused where the scalar code calls Fma), so
// both give the same floats; AVX-512 is used when the running CPU has it. Tests turn the vector
// paths off to check that claim bit for bit.
namespace owval::engine::internal {

// True when the running CPU has AVX-512F and the vector paths are not switched off.
bool UseAvx512();
// Switches the vector paths off (true) or back to the CPU's choice (false). Not thread-safe:
// call between runs.
void ForceScalarPaths(bool scalar);

}  // namespace owval::engine::internal
