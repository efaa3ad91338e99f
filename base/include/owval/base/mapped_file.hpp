#pragma once
// A read-only memory map of a whole file: large trajectories are parsed in place, without the
// copy (and the page-by-page faults of a fresh buffer) that reading into a string costs.
#include <filesystem>
#include <string_view>

namespace owval {

class MappedFile {
 public:
  // Throws InputError naming the file when it is missing, a directory or unreadable.
  explicit MappedFile(const std::filesystem::path& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  std::string_view text() const { return {data_, size_}; }

 private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

// Asks the kernel to back [data, data + bytes) with transparent huge pages (2 MiB), which cuts
// page faults by 512x when a large array is first filled. A hint: harmless when unsupported.
void AdviseHugePages(void* data, std::size_t bytes);

}  // namespace owval
