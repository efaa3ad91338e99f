#pragma once
// Runs a piece of work in a child process, so that a crash inside a third-party library (libhdf5
// 1.10.8 dereferences NULL in H5Aopen_by_idx on some corrupt attribute tables) becomes a refusal
// naming the file instead of owval's crash (issue 18 item 6). The work's effects stay in the
// child: use it for a dry run whose success makes the real, in-process run safe.
#include <functional>
#include <string>

namespace owval {

struct ContainedOptions {
  int timeout_s = 120;  // the child is killed past this (a library looping on corrupt data)
};

// Runs `work` in a forked child. Returns when it completes. Throws InputError with the child's
// message when `work` threw InputError; InputError(file, "<what> crashed ...") when the child
// died by a signal, a sanitizer's report or the timeout; std::runtime_error with the child's
// message for any other exception. `work` must not use OpenMP (a forked child has no thread pool).
void RunContained(const std::string& file, const std::string& what,
                  const std::function<void()>& work, const ContainedOptions& options = {});

}  // namespace owval
