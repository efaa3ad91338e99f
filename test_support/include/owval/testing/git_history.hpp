#pragma once
// A git history for tests of the checklist's item 1 (the prediction committed before the runs),
// made with the real git command: cli/tests/checklist_test.cpp and ci/tests/git_order_test.cpp.
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace owval::testing {

// A repository in `dir` (its files already there): an empty first commit tagged "base", then one
// commit per entry of `commits`, adding those files. Throws when a git command fails.
inline void CommitInOrder(const std::filesystem::path& dir,
                          const std::vector<std::vector<std::string>>& commits) {
  const auto git = [&](const std::string& args) {
    const std::string command = "git -C '" + dir.string() +
                                "' -c user.name=t -c user.email=t@t -c commit.gpgsign=false " +
                                args + " > /dev/null 2>&1";
    if (std::system(command.c_str()) != 0) throw std::runtime_error("failed: " + command);
  };
  git("init -q");
  git("commit -q --allow-empty -m base");
  git("tag base");
  for (const std::vector<std::string>& files : commits) {
    std::string list;
    for (const std::string& file : files) list += " " + file;
    git("add" + list);
    git("commit -q -m step");
  }
}

}  // namespace owval::testing
