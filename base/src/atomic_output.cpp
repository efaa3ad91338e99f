#include "owval/base/atomic_output.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <atomic>
#include <sstream>

#include "owval/base/errors.hpp"
#include "owval/base/input_file.hpp"
#include "signal_cleanup.hpp"

namespace owval {
namespace fs = std::filesystem;

namespace {

// Temporaries of a process that died before it could remove them (SIGKILL, a power cut; a
// signal's default action skips destructors): ".NAME.tmp.PID.N" beside the destination whose PID
// no longer runs. Removed by the next writer of the same destination.
void SweepStaleTemporaries(const fs::path& destination) {
  std::string prefix(1, '.');  // ".NAME.tmp." (built in steps: GCC 12's -Wrestrict misfires on
  prefix += destination.filename().string();  // "." + string)
  prefix += ".tmp.";
  std::error_code ec;
  const fs::path parent = destination.parent_path().empty() ? "." : destination.parent_path();
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const long pid = std::atol(name.c_str() + prefix.size());
    if (pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) fs::remove_all(entry.path(), ec);
  }
}

fs::path TemporarySibling(const fs::path& destination) {
  static std::atomic<int> counter{0};
  std::ostringstream name;
  name << "." << destination.filename().string() << ".tmp." << ::getpid() << "." << counter++;
  return destination.parent_path() / name.str();
}
}  // namespace

AtomicOutput::AtomicOutput(fs::path destination)
    : destination_(std::move(destination)), temporary_(TemporarySibling(destination_)) {
  RefuseSpecialFileOutput(destination_);
  RefuseSymlinkOutput(destination_);
  CreateOutputDirectories(destination_.parent_path());
  signal_slot_ = internal::RememberTemporary(fs::absolute(temporary_));
}

AtomicOutput::~AtomicOutput() {
  internal::ForgetTemporary(&signal_slot_);
  if (committed_) return;
  if (stream_.is_open()) stream_.close();
  if (keep_) return;
  std::error_code ignored;
  fs::remove(temporary_, ignored);
}

std::ofstream& AtomicOutput::stream() {
  if (!stream_.is_open()) {
    stream_.open(temporary_, std::ios::binary | (append_ ? std::ios::app : std::ios::trunc));
    if (!stream_)  // errno names why (ofstream does not); the temporary is not the user's name
      throw InputError(destination_.string(), 0,
                       std::string("cannot open for writing: ") + std::strerror(errno));
  }
  return stream_;
}

void AtomicOutput::Adopt(const fs::path& existing) {
  if (stream_.is_open()) throw std::logic_error("AtomicOutput::Adopt after the stream opened");
  internal::ForgetTemporary(&signal_slot_);  // a resumed run's output: kept for the next resume
  temporary_ = existing;
  append_ = keep_ = true;
}

void AtomicOutput::Commit() { CommitAs(destination_); }

void AtomicOutput::KeepOnFailure() {
  internal::ForgetTemporary(&signal_slot_);  // for --resume, even after a signal
  keep_ = true;
}

void AtomicOutput::CloseStream(const fs::path& named) {
  if (!stream_.is_open()) return;
  stream_.flush();
  if (!stream_) throw InputError(named.string(), 0, "write failed (disk full?)");
  stream_.close();
  if (stream_.fail()) throw InputError(named.string(), 0, "write failed (disk full?)");
}

void AtomicOutput::Release() {
  CloseStream(destination_);
  internal::ForgetTemporary(&signal_slot_);
  committed_ = true;  // the temporary is the new owner's
}

fs::path CommitMarkerPath(const fs::path& directory) { return directory / ".owval-commit"; }

OutputGroup::~OutputGroup() {
  for (Member& m : members_) internal::ForgetTemporary(&m.signal_slot);
  if (committed_) return;
  std::error_code ignored;
  for (const Member& m : members_)
    if (!m.temporary.empty()) fs::remove_all(m.temporary, ignored);
}

void OutputGroup::Adopt(AtomicOutput* finished) {
  finished->Release();
  members_.push_back({finished->temporary_path(), finished->destination(),
                      internal::RememberTemporary(fs::absolute(finished->temporary_path()))});
}

fs::path OutputGroup::Stage(const fs::path& destination) {
  SweepStaleTemporaries(destination);
  const fs::path temporary = TemporarySibling(destination);
  members_.push_back(
      {temporary, destination, internal::RememberTemporary(fs::absolute(temporary))});
  return members_.back().temporary;
}

fs::path OutputGroup::TemporaryOf(const fs::path& destination) const {
  for (const Member& m : members_)
    if (m.destination == destination) return m.temporary;
  return {};
}

void OutputGroup::Retire(const fs::path& destination, bool is_ours) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(destination, error);
  const bool file = fs::is_regular_file(status) || fs::is_symlink(status);
  if (file || (fs::is_directory(status) && is_ours)) members_.push_back({fs::path(), destination});
}

void OutputGroup::Commit() {
  if (members_.empty()) {
    committed_ = true;
    return;
  }
  const fs::path directory = members_.front().destination.parent_path();
  std::string names;
  for (const Member& m : members_) {
    if (m.destination.parent_path() != directory)
      throw std::logic_error("OutputGroup: members in more than one directory");
    names += m.destination.filename().string() + "\n";
  }
  // A directory is replaced only by a directory (whose writer checked it may replace it): a
  // user's directory in the way of a file is refused before anything is removed.
  std::error_code error;
  for (const Member& m : members_) RefuseSpecialFileOutput(m.destination);
  for (const Member& m : members_)
    if (!m.temporary.empty() && fs::is_directory(fs::symlink_status(m.destination, error)) &&
        !fs::is_directory(fs::symlink_status(m.temporary, error)))
      throw InputError(m.destination.string(), 0, "is a directory; expected a file to write");
  const fs::path marker = CommitMarkerPath(directory);
  WriteFileAtomically(marker, names);
  for (const Member& m : members_) {  // older outputs
    if (fs::is_directory(fs::symlink_status(m.destination, error)))
      fs::remove_all(m.destination, error);
    else
      fs::remove(m.destination, error);
  }
  for (Member& m : members_) {
    if (m.temporary.empty()) continue;  // retired
    fs::rename(m.temporary, m.destination, error);
    internal::ForgetTemporary(&m.signal_slot);
    if (error)  // the marker stays: the set in place is incomplete and readers say so
      throw InputError(m.destination.string(), 0, "cannot rename into place: " + error.message());
  }
  committed_ = true;
  fs::remove(marker, error);
}

void AtomicOutput::CommitAs(const fs::path& destination) {
  CloseStream(destination);
  RefuseSpecialFileOutput(destination);  // nothing of the kind was put there while the work ran
  std::error_code error;
  fs::rename(temporary_, destination, error);
  if (error)
    throw InputError(destination.string(), 0, "cannot rename into place: " + error.message());
  internal::ForgetTemporary(&signal_slot_);
  committed_ = true;
}

fs::path OwvalDirectoryMarker(const fs::path& directory) { return directory / ".owval-directory"; }

void MarkOwvalDirectory(const fs::path& directory) {
  std::ofstream(OwvalDirectoryMarker(directory)) << "written by owval; owval replaces it whole\n";
}

AtomicDirectory::AtomicDirectory(fs::path destination)
    : AtomicDirectory(std::move(destination), [](const fs::path& existing) {
        std::error_code error;
        return fs::is_regular_file(OwvalDirectoryMarker(existing), error);
      }) {
  MarkOwvalDirectory(temporary_);
}

AtomicDirectory::AtomicDirectory(fs::path destination,
                                 std::function<bool(const fs::path&)> replaceable)
    : destination_(std::move(destination)),
      temporary_(TemporarySibling(destination_)),
      replaceable_(std::move(replaceable)) {
  CheckReplaceable();
  SweepStaleTemporaries(destination_);
  CreateOutputDirectories(destination_.parent_path());
  std::error_code error;
  fs::create_directory(temporary_, error);  // a sibling: errors name the destination
  if (error) throw InputError(destination_.string(), 0, "cannot be created: " + error.message());
  signal_slot_ = internal::RememberTemporary(fs::absolute(temporary_));
}

void AtomicDirectory::CheckReplaceable() const {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(destination_, error);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status))
    throw InputError(destination_.string(), 0,
                     "exists and is not a directory; expected a directory to write");
  if (fs::is_empty(destination_, error) || replaceable_(destination_)) return;
  throw InputError(destination_.string(), 0,
                   "is a directory owval did not write; refusing to replace it (name a new or "
                   "empty directory)");
}

AtomicDirectory::~AtomicDirectory() {
  internal::ForgetTemporary(&signal_slot_);
  if (committed_) return;
  std::error_code ignored;
  fs::remove_all(temporary_, ignored);
}

void AtomicDirectory::Commit() {
  CheckReplaceable();  // nothing of the user's was put there while the work ran
  std::error_code error;
  const fs::path old = TemporarySibling(destination_);
  const bool replacing = fs::exists(destination_, error);
  if (replacing) fs::rename(destination_, old, error);
  if (!error) fs::rename(temporary_, destination_, error);
  if (error)
    throw InputError(destination_.string(), 0, "cannot move into place: " + error.message());
  internal::ForgetTemporary(&signal_slot_);
  committed_ = true;
  if (replacing) fs::remove_all(old, error);  // the older report, now out of the way
}

void WriteFilesTogether(const std::vector<std::pair<fs::path, std::string>>& files) {
  OutputGroup group;
  for (const auto& [destination, contents] : files) {
    AtomicOutput out(destination);
    out.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
    group.Adopt(&out);
  }
  group.Commit();
}

void WriteFileAtomically(const fs::path& destination, const std::string& contents) {
  SweepStaleTemporaries(destination);
  AtomicOutput out(destination);
  out.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  out.Commit();
}

std::string ReadWholeFile(const fs::path& path) {
  RequireInputFile(path);  // before open(): a FIFO would block it
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open file (missing or unreadable)");
  std::error_code error;
  const auto size = fs::file_size(path, error);
  if (error || fs::is_directory(path)) throw InputError(path.string(), 0, "not a regular file");
  std::string contents(size, '\0');
  in.read(contents.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size)
    throw InputError(path.string(), 0, "read failed (file changed while reading?)");
  return contents;
}

}  // namespace owval
