#include "signal_cleanup.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

#include "owval/base/atomic_output.hpp"

namespace owval {
namespace {

constexpr int kSlots = 128;
constexpr std::size_t kPathBytes = 4096;

enum SlotState : int { kFree = 0, kFilling = 1, kLive = 2 };

// `owner`: the process that remembered the path. A forked child (RunContained's, a test's) inherits
// the table and the handler, and must never remove its parent's files (a test's scratch directory).
struct Slot {
  std::atomic<int> state{kFree};
  bool folder_if_empty = false;
  pid_t owner = 0;
  char path[kPathBytes];
};
Slot g_slots[kSlots];

// Only system calls from here on: the handler may have interrupted malloc or a lock holder.
void RemoveTree(int parent, const char* name, int depth);

void RemoveEntriesOf(int dir, int depth) {
  alignas(8) char buffer[4096];
  for (;;) {
    const long n = ::syscall(SYS_getdents64, dir, buffer, sizeof buffer);
    if (n <= 0) return;
    for (long at = 0; at < n;) {
      const auto* entry = reinterpret_cast<const dirent64*>(buffer + at);
      at += entry->d_reclen;
      const char* name = entry->d_name;
      if (std::strcmp(name, ".") == 0 || std::strcmp(name, "..") == 0) continue;
      RemoveTree(dir, name, depth + 1);
    }
  }
}

void RemoveTree(int parent, const char* name, int depth) {
  if (::unlinkat(parent, name, 0) == 0 || depth > 16) return;
  const int dir = ::openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (dir < 0) return;
  RemoveEntriesOf(dir, depth);
  ::close(dir);
  ::unlinkat(parent, name, AT_REMOVEDIR);
}

extern "C" void RemoveTemporariesAndDie(int signal) {
  const pid_t self = ::getpid();
  const auto mine = [self](const Slot& s) {
    return s.state.load(std::memory_order_acquire) == kLive && s.owner == self;
  };
  for (Slot& s : g_slots)
    if (mine(s) && !s.folder_if_empty) RemoveTree(AT_FDCWD, s.path, 0);
  for (Slot& s : g_slots)  // registered innermost first; rmdir fails on a folder not empty
    if (mine(s) && s.folder_if_empty) ::rmdir(s.path);
  std::signal(signal, SIG_DFL);  // then die of it, as without the handler (exit 130/143)
  std::raise(signal);
}

}  // namespace

namespace internal {

namespace {
int Remember(const std::filesystem::path& path, bool folder_if_empty) {
  const std::string& text = path.native();
  if (text.empty() || text.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_slots[i].state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(g_slots[i].path, text.c_str(), text.size() + 1);
    g_slots[i].folder_if_empty = folder_if_empty;
    g_slots[i].owner = ::getpid();
    g_slots[i].state.store(kLive, std::memory_order_release);
    return i;
  }
  return -1;
}
}  // namespace

int RememberTemporary(const std::filesystem::path& path) { return Remember(path, false); }
int RememberEmptyFolder(const std::filesystem::path& path) { return Remember(path, true); }

void ForgetTemporary(int* slot) {
  if (*slot >= 0) g_slots[*slot].state.store(kFree, std::memory_order_release);
  *slot = -1;
}

}  // namespace internal

void RemoveTemporariesOnSignal() {
  for (int signal : {SIGINT, SIGTERM}) {
    // A signal the parent ignored (nohup, a background job) stays ignored.
    struct sigaction previous {};
    if (::sigaction(signal, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN) continue;
    std::signal(signal, RemoveTemporariesAndDie);
  }
}

}  // namespace owval
