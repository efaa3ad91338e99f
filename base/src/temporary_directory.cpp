#include "owval/base/temporary_directory.hpp"

#include <stdlib.h>

#include <cerrno>
#include <system_error>

#include "owval/base/errors.hpp"
#include "signal_cleanup.hpp"

namespace owval {
namespace fs = std::filesystem;

TemporaryDirectory::TemporaryDirectory(const std::string& prefix, OnExit on_exit)
    : on_exit_(on_exit) {
  const fs::path parent = fs::absolute(fs::temp_directory_path());
  std::string pattern = (parent / (prefix + "-XXXXXX")).string();
  if (!::mkdtemp(pattern.data()))
    throw EnvironmentError("cannot create a temporary directory under " + parent.string() + ": " +
                           std::generic_category().message(errno));
  path_ = pattern;
  if (!kept()) signal_slot_ = internal::RememberTemporary(path_);
}

TemporaryDirectory::~TemporaryDirectory() {
  if (kept()) return;
  std::error_code ignored;  // a destructor must not throw
  fs::remove_all(path_, ignored);
  internal::ForgetTemporary(&signal_slot_);  // after: a signal meanwhile removes the rest
}

}  // namespace owval
