#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"
#include "signal_cleanup.hpp"

namespace owval {
namespace fs = std::filesystem;

namespace {

// What stops a new entry in an existing directory, in words: errno alone misleads (/proc answers
// ENOENT for a directory that exists).
std::string RefusalReason(const fs::path& directory, int error) {
  const std::string d = directory.string();
  switch (error) {
    case EACCES:
    case EPERM:
      return d + " is not writable (permission denied)";
    case EROFS:
      return d + " is on a read-only file system";
    case ENOENT:
      return d + " accepts no new files (a virtual file system such as /proc or /sys)";
    case ENOSPC:
    case EDQUOT:
      return d + " is full (no space left or quota exceeded)";
    default:
      return d + ": " + std::strerror(error);
  }
}

// access() says yes to root everywhere but a read-only mount, yet /proc, /sys or a FUSE folder
// still refuse a new file: create (and remove) an empty one to know.
void ProbeNewFile(const std::string& named, const std::string& verb, const fs::path& directory) {
  static std::atomic<int> counter{0};  // CheckOutputPath may be called from several threads
  const fs::path probe =
      directory / (".owval-probe." + std::to_string(::getpid()) + "." + std::to_string(counter++));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) throw InputError(named, 0, verb + ": " + RefusalReason(directory, errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

// The nearest existing ancestor of `path` (the working directory for a relative path's first
// component), and the outermost missing directory below it (empty when path's parent exists).
struct Ancestry {
  fs::path existing, first_missing;
};
Ancestry AncestryOf(const fs::path& path) {
  std::error_code error;
  Ancestry a;
  a.existing = path.parent_path();
  while (!a.existing.empty() && !fs::exists(a.existing, error) &&
         a.existing != a.existing.parent_path()) {
    a.first_missing = a.existing;
    a.existing = a.existing.parent_path();
  }
  if (a.existing.empty()) a.existing = ".";
  return a;
}

// The ancestor decides whether `path` (and the directories above it) can be made: errors name
// the outermost directory that must be created, else `path` itself (the user's own words).
void CheckAncestor(const fs::path& path, const Ancestry& a) {
  const bool creates = !a.first_missing.empty();
  const std::string named = creates ? a.first_missing.string() : path.string();
  const std::string verb = creates ? "cannot be created" : "cannot be written";
  std::error_code error;
  if (!fs::is_directory(a.existing, error))
    throw InputError(named, 0, verb + ": " + a.existing.string() + " is not a directory");
  if (::access(a.existing.c_str(), W_OK | X_OK) != 0)
    throw InputError(named, 0, verb + ": " + RefusalReason(a.existing, errno));
  ProbeNewFile(named, verb, a.existing);
}

}  // namespace

void RefuseSpecialFileOutput(const fs::path& destination) {
  std::error_code error;
  const fs::file_status status = fs::status(destination, error);
  if (fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status))
    throw InputError(destination.string(), 0,
                     "is a device, FIFO or socket, not a regular file; expected a file to write");
}

void RefuseSymlinkOutput(const fs::path& destination) {
  std::error_code error;
  if (fs::is_symlink(fs::symlink_status(destination, error)))
    throw InputError(destination.string(), 0,
                     "is a symbolic link; name its target (an output is replaced whole, which "
                     "would replace the link)");
}

void CheckOutputPath(const fs::path& destination) {
  if (destination.empty()) throw InputError("output path is empty");
  std::error_code error;
  if (fs::is_directory(destination, error))
    throw InputError(destination.string(), 0, "is a directory; expected a file to write");
  RefuseSpecialFileOutput(destination);
  RefuseSymlinkOutput(destination);
  CheckAncestor(destination, AncestryOf(destination));
}

void CheckOutputDirectory(const fs::path& directory) {
  if (directory.empty()) throw InputError("output directory is empty");
  std::error_code error;
  const fs::file_status status = fs::status(directory, error);
  if (fs::exists(status) && !fs::is_directory(status))
    throw InputError(directory.string(), 0, "exists and is not a directory; expected a directory");
  // Written as a temporary sibling and renamed: its parent (or the nearest existing ancestor)
  // must take new entries; errors name the directory, or the outermost one to create above it.
  Ancestry a = AncestryOf(directory);
  if (a.first_missing.empty()) a.first_missing = directory;
  CheckAncestor(directory, a);
}

void CheckOutputIsNotAnInput(const fs::path& output, const std::vector<fs::path>& inputs) {
  for (const fs::path& input : inputs) {
    std::error_code error;  // false, not an error, when either does not exist
    if (!input.empty() && fs::equivalent(output, input, error))
      throw InputError(
          output.string(), 0,
          "is also an input of this command (" + input.string() + "); name another output");
  }
}

void CreateOutputDirectories(const fs::path& directory) {
  if (directory.empty()) return;
  std::error_code error;
  if (fs::is_directory(directory, error)) return;
  const Ancestry a = AncestryOf(directory / "x");
  fs::create_directories(directory, error);
  if (!error) return;
  const fs::path named = a.first_missing.empty() ? directory : a.first_missing;
  if (error.value() == ENOTDIR || error.value() == EEXIST)
    throw InputError(named.string(), 0,
                     "cannot be created: " + a.existing.string() + " is not a directory");
  throw InputError(named.string(), 0,
                   "cannot be created: " + RefusalReason(a.existing, error.value()));
}

MissingDirectories::MissingDirectories(const fs::path& directory) {
  std::error_code error;
  for (fs::path d = directory; !d.empty() && !fs::exists(d, error); d = d.parent_path()) {
    missing_.push_back(d);
    signal_slots_.push_back(internal::RememberEmptyFolder(fs::absolute(d)));
    if (d == d.parent_path()) break;
  }
}

void MissingDirectories::Keep() {
  for (int& slot : signal_slots_) internal::ForgetTemporary(&slot);
  keep_ = true;
}

MissingDirectories::~MissingDirectories() {
  for (int& slot : signal_slots_) internal::ForgetTemporary(&slot);
  if (keep_) return;
  std::error_code error;
  for (const fs::path& d : missing_) fs::remove(d, error);  // only if empty
}

ScratchFile::ScratchFile(fs::path path)
    : path_(std::move(path)), signal_slot_(internal::RememberTemporary(fs::absolute(path_))) {}

void ScratchFile::Keep() {
  internal::ForgetTemporary(&signal_slot_);
  keep_ = true;
}

ScratchFile::~ScratchFile() {
  internal::ForgetTemporary(&signal_slot_);
  if (keep_) return;
  std::error_code error;
  fs::remove(path_, error);
}

}  // namespace owval
