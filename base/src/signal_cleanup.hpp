#pragma once
// The temporaries of unfinished outputs, removed when SIGINT or SIGTERM ends the process (the
// signal's default action skips destructors, so AtomicOutput and its kin cannot). A fixed table,
// so that the handler touches no allocator and no lock: 128 slots; a temporary beyond them is left
// to the next writer's sweep (SweepStaleTemporaries).
#include <filesystem>

namespace owval::internal {

// The slot that holds `path` until Forget, or -1 when the table is full. A temporary is removed
// whole; an empty folder (MissingDirectories') only when it is left empty, after the temporaries.
int RememberTemporary(const std::filesystem::path& path);
int RememberEmptyFolder(const std::filesystem::path& path);
void ForgetTemporary(int* slot);  // sets *slot to -1; no-op for -1

}  // namespace owval::internal
