#include "owval/base/input_file.hpp"

#include <fstream>
#include <string>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"

namespace owval {
namespace fs = std::filesystem;
namespace {

// Whether an interrupted OutputGroup::Commit in the file's directory names it.
// A marker that is not a regular file is none owval wrote: a FIFO of that name would block the
// ifstream's open() until a writer appeared, and every reader in its directory with it.
bool NamedByCommitMarker(const fs::path& path) {
  const fs::path marker_path =
      CommitMarkerPath(path.parent_path().empty() ? "." : path.parent_path());
  std::error_code error;
  if (!fs::is_regular_file(marker_path, error)) return false;
  std::ifstream marker(marker_path);
  const std::string name = path.filename().string();
  for (std::string line; marker && std::getline(marker, line);)
    if (line == name) return true;
  return false;
}

// Throws unless `path` is of type `wanted` (a regular file or a directory); expected: what the
// caller reads ("a regular file", "a backends file (JSON, docs/backends.md)").
void RequireType(const fs::path& path, fs::file_type wanted, const std::string& expected) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  const std::string name = path.string();
  const std::string want = ", expected " + expected;
  if (status.type() == wanted) return;
  switch (status.type()) {
    case fs::file_type::not_found:
      throw InputError(
          name, 0,
          (wanted == fs::file_type::directory ? "missing" : "cannot open file (missing)") + want);
    case fs::file_type::regular:
      throw InputError(name, 0, "is a file" + want);
    case fs::file_type::directory:
      throw InputError(name, 0, "is a directory" + want);
    case fs::file_type::fifo:
      throw InputError(name, 0, "is a FIFO (named pipe)" + want);
    case fs::file_type::block:
    case fs::file_type::character:
      throw InputError(name, 0, "is a device" + want);
    case fs::file_type::socket:
      throw InputError(name, 0, "is a socket" + want);
    default:
      throw InputError(name, 0, "cannot open file (unreadable or not a regular file)" + want);
  }
}

}  // namespace

void RequireInputFile(const fs::path& path, const std::string& expected) {
  RequireType(path, fs::file_type::regular, expected);
  if (NamedByCommitMarker(path))
    throw InputError(path.string(), 0,
                     "incomplete: the command that wrote it stopped while moving its outputs into "
                     "place (.owval-commit names it); run it again");
}

void RequireInputDirectory(const fs::path& path, const std::string& expected) {
  RequireType(path, fs::file_type::directory, expected);
}

}  // namespace owval
