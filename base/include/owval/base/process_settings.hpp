#pragma once
// Settings that belong to the whole process, made by the application (owval's main) at start-up
// and never by a library behind its caller's back.
namespace owval {

// HDF5 allocates and frees a buffer per chunk. With glibc's default thresholds, buffers of a few
// MiB are fresh mmaps (or trimmed heap) every time, and page faults then cost more than inflating
// the data: keeping such buffers on the heap makes trajectory reads several times faster
// (docs/benchmarks.md, `owval bench io`). Raises glibc's mmap and trim thresholds.
void KeepLargeBuffersOnHeap();

}  // namespace owval
