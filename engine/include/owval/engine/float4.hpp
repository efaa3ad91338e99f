#pragma once
// The engine's per-particle record, as Sibernetic's kernels store it (OpenCL float4).

namespace owval::engine {

// Four floats per particle: a position in configuration units (cu) with the type code in w, a
// velocity in m/s (a boundary particle's velocity slot holds its wall normal), or an
// acceleration in m/s^2.
struct Float4 {
  float x = 0, y = 0, z = 0, w = 0;
};

}  // namespace owval::engine
