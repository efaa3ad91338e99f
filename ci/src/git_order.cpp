// Item 1's order check: in BASE..HEAD, was prediction.json committed no later than the first
// trajectory? Reads the history with the real git command (argument vector, no shell).
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <map>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/ci/checklist.hpp"

extern char** environ;

namespace owval::ci {
namespace fs = std::filesystem;
namespace {

// Runs git with `args` in `cwd`; returns stdout. InputError naming `range` otherwise.
std::string Git(const fs::path& cwd, const std::string& range, std::vector<std::string> args) {
  args.insert(args.begin(), {"git", "-C", cwd.string()});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int out[2];
  if (::pipe(out) != 0) throw InputError("cannot create a pipe to run git");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, out[0]);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "git", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t n; spawned == 0 && (n = ::read(out[0], buffer, sizeof buffer)) > 0;)
    text.append(buffer, std::size_t(n));
  ::close(out[0]);
  if (spawned != 0) throw InputError("--git-range: cannot run git");
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError("--git-range " + range + ": git cannot read this range in " + cwd.string());
  return text;
}

constexpr const char* kTrajectoryNames[] = {"reference.h5", "reference.txt", "candidate.h5",
                                            "candidate.txt"};

bool IsTrajectory(const std::string& name) {
  const std::string base = fs::path(name).filename().string();
  return base.rfind("reference.", 0) == 0 || base.rfind("candidate.", 0) == 0;
}

}  // namespace

void CheckGitRange(const fs::path& directory, const std::string& git_range) {
  const auto dots = git_range.find("..");
  if (dots == std::string::npos || dots == 0 || git_range.find("..", dots + 2) != std::string::npos)
    throw InputError("--git-range " + git_range + ": expected BASE..HEAD");
  Git(directory, git_range, {"rev-list", "--count", git_range});
}

bool PredictionCommittedFirst(const fs::path& directory, const std::string& git_range,
                              std::string* detail) {
  CheckGitRange(directory, git_range);
  const std::string base = git_range.substr(0, git_range.find(".."));
  // Whether `name` (a file under the directory) already existed at BASE.
  auto at_base = [&](const std::string& name) {
    return !Git(directory, git_range, {"ls-tree", "--name-only", base, "--", name}).empty();
  };
  // Commits oldest first, each followed by the files it added under the directory.
  const std::string log = Git(directory, git_range,
                              {"log", "--reverse", "--diff-filter=A", "--format=@%h", "--name-only",
                               "--relative", git_range, "--", "."});
  std::istringstream in(log);
  std::size_t index = 0;
  std::optional<std::size_t> prediction_at, trajectory_at;
  std::string prediction_commit, trajectory_commit, commit;
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    if (line[0] == '@') {
      commit = line.substr(1);
      ++index;
    } else if (fs::path(line).filename() == "prediction.json" && !prediction_at) {
      prediction_at = index, prediction_commit = commit;
    } else if (IsTrajectory(line) && !trajectory_at) {
      trajectory_at = index, trajectory_commit = commit;
    }
  }
  if (!trajectory_at) {
    // The runs predate the range: a prediction added in it came after them.
    const bool runs_at_base =
        std::any_of(std::begin(kTrajectoryNames), std::end(kTrajectoryNames), at_base);
    if (prediction_at && runs_at_base) {
      *detail = "prediction.json committed in " + prediction_commit +
                ", after the trajectories (already at " + base + "): prediction AFTER the run";
      return false;
    }
    *detail = "order not checked: no trajectory was added in " + git_range;
    return true;
  }
  if (!prediction_at) {
    const bool before = at_base("prediction.json");
    *detail = before ? "prediction.json predates " + git_range
                     : "prediction.json was not committed before the first trajectory (" +
                           trajectory_commit + ")";
    return before;
  }
  const bool first = *prediction_at <= *trajectory_at;
  *detail = "prediction.json committed in " + prediction_commit + ", first trajectory in " +
            trajectory_commit + (first ? ": prediction first" : ": prediction AFTER the run");
  return first;
}

}  // namespace owval::ci
