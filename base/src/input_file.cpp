#include "owval/base/input_file.hpp"

#include <fstream>
#include <string>

#include "owval/base/atomic_output.hpp"
#include "owval/base/errors.hpp"

namespace owval {
namespace fs = std::filesystem;
namespace {

// Whether an interrupted OutputGroup::Commit in the file's directory names it.
bool NamedByCommitMarker(const fs::path& path) {
  std::ifstream marker(CommitMarkerPath(path.parent_path().empty() ? "." : path.parent_path()));
  const std::string name = path.filename().string();
  for (std::string line; marker && std::getline(marker, line);)
    if (line == name) return true;
  return false;
}

void RequireRegularFile(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  const std::string name = path.string();
  switch (status.type()) {
    case fs::file_type::regular:
      return;
    case fs::file_type::not_found:
      throw InputError(name, 0, "cannot open file (missing)");
    case fs::file_type::directory:
      throw InputError(name, 0, "is a directory, expected a regular file");
    case fs::file_type::fifo:
      throw InputError(name, 0, "is a FIFO (named pipe), expected a regular file");
    case fs::file_type::block:
    case fs::file_type::character:
      throw InputError(name, 0, "is a device, expected a regular file");
    case fs::file_type::socket:
      throw InputError(name, 0, "is a socket, expected a regular file");
    default:
      throw InputError(name, 0, "cannot open file (unreadable or not a regular file)");
  }
}

}  // namespace

void RequireInputFile(const fs::path& path) {
  RequireRegularFile(path);
  if (NamedByCommitMarker(path))
    throw InputError(path.string(), 0,
                     "incomplete: the command that wrote it stopped while moving its outputs into "
                     "place (.owval-commit names it); run it again");
}

}  // namespace owval
