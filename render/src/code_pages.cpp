#include "code_pages.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <cstdio>
#include <fstream>

namespace owval::render::internal {

std::size_t ReleaseLibraryCode(const std::string& library) {
  std::ifstream maps("/proc/self/maps");
  std::size_t released = 0;
  // A line: "start-end perms offset dev inode path"; only "r-xp" mappings (read, execute, no
  // write, private) are code that is identical to the file.
  for (std::string line; std::getline(maps, line);) {
    unsigned long long start = 0, end = 0;
    char perms[5] = {};
    if (std::sscanf(line.c_str(), "%llx-%llx %4s", &start, &end, perms) != 3) continue;
    if (std::string(perms) != "r-xp" || line.find(library) == std::string::npos) continue;
    void* address = reinterpret_cast<void*>(static_cast<std::uintptr_t>(start));
    if (madvise(address, end - start, MADV_DONTNEED) == 0) released += end - start;
  }
  return released;
}

}  // namespace owval::render::internal
