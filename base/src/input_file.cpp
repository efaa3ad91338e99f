#include "owval/base/input_file.hpp"

#include "owval/base/errors.hpp"

namespace owval {

void RequireRegularFile(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
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

}  // namespace owval
