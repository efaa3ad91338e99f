#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"

namespace owval {
namespace fs = std::filesystem;

namespace {

// access() says yes to root everywhere but a read-only mount, yet /proc, /sys or a FUSE folder
// still refuse a new file: create (and remove) an empty one to know.
void ProbeNewFile(const fs::path& destination, const fs::path& directory) {
  static std::atomic<int> counter{0};  // CheckOutputPath may be called from several threads
  const fs::path probe =
      directory / (".owval-probe." + std::to_string(::getpid()) + "." + std::to_string(counter++));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0)
    throw InputError(destination.string(), 0,
                     "cannot be written: " + directory.string() + ": " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace

void CheckOutputPath(const fs::path& destination) {
  if (destination.empty()) throw InputError("output path is empty");
  std::error_code error;
  if (fs::is_directory(destination, error))
    throw InputError(destination.string(), 0, "is a directory; expected a file to write");
  // The nearest existing ancestor decides whether the missing directories can be created. A
  // relative path's ancestors end at its first component ("reports" of "reports/a/index.html"),
  // whose parent is the working directory.
  fs::path existing = destination.parent_path();
  while (!existing.empty() && !fs::exists(existing, error) && existing != existing.parent_path())
    existing = existing.parent_path();
  if (existing.empty()) existing = ".";
  if (!fs::is_directory(existing, error))
    throw InputError(destination.string(), 0,
                     "cannot be written: " + existing.string() + " is not a directory");
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw InputError(destination.string(), 0,
                     "cannot be written: " + existing.string() + " is not writable");
  ProbeNewFile(destination, existing);
}

MissingDirectories::MissingDirectories(const fs::path& directory) {
  std::error_code error;
  for (fs::path d = directory; !d.empty() && !fs::exists(d, error); d = d.parent_path()) {
    missing_.push_back(d);
    if (d == d.parent_path()) break;
  }
}

MissingDirectories::~MissingDirectories() {
  if (keep_) return;
  std::error_code error;
  for (const fs::path& d : missing_) fs::remove(d, error);  // only if empty
}

}  // namespace owval
