#pragma once
// Releasing a shared library's machine code from the resident set (issue 16's memory bound).
//
// OSMesa's llvmpipe compiles its shaders with libLLVM while the first frame is drawn; after
// that no LLVM code runs for the rest of a video, yet the pages of libLLVM's code that its
// static constructors and the compiler touched (about 55 MB) stay mapped and count in the
// process's resident memory: a third of a 1280x720 render's peak. They are clean file pages
// (read-only, executable, never written), so dropping them from the process (madvise
// MADV_DONTNEED) loses nothing: a page the process runs again is read back from the page cache.
#include <cstddef>
#include <string>

namespace owval::render::internal {

// Drops the resident pages of every read-only executable mapping whose file path contains
// `library` (e.g. "libLLVM"); returns the bytes of address space advised. Writable or
// non-executable mappings (relocated data, the heap) are never touched.
std::size_t ReleaseLibraryCode(const std::string& library);

}  // namespace owval::render::internal
