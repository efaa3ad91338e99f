#include "owval/base/process_settings.hpp"

#include <malloc.h>

namespace owval {

void KeepLargeBuffersOnHeap() {
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace owval
