#pragma once
// Output files appear whole or not at all: write to a temporary sibling, then Commit() renames it
// over the destination. A destroyed AtomicOutput that was never committed removes its temporary,
// so an error or Ctrl-C leaves no partial file behind.
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace owval {

class AtomicOutput {
 public:
  explicit AtomicOutput(std::filesystem::path destination);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  // Path to write to (for libraries that open files themselves, e.g. HDF5 or libavformat).
  const std::filesystem::path& temporary_path() const { return temporary_; }
  const std::filesystem::path& destination() const { return destination_; }
  // A binary stream on the temporary file, opened on first use.
  std::ofstream& stream();
  // Flushes, closes and renames the temporary onto the destination. Throws on I/O failure.
  void Commit();
  // The same, onto another name (a partial trajectory's, when a run is interrupted).
  void CommitAs(const std::filesystem::path& destination);
  // Continues an existing file instead of a new temporary (a resumed run's output): stream()
  // then appends to it, Commit() renames it onto the destination, and an uncommitted output
  // leaves it in place for the next resume.
  void Adopt(const std::filesystem::path& existing);
  // Keep the temporary when destroyed uncommitted (a checkpointed run's output, for --resume).
  void KeepOnFailure();
  // Flushes and closes the temporary and hands it over (to an OutputGroup): this object then
  // neither renames nor removes it. Throws on I/O failure.
  void Release();

 private:
  // Flushes and closes the stream if open; InputError naming `named` on I/O failure.
  void CloseStream(const std::filesystem::path& named);

  std::filesystem::path destination_;
  std::filesystem::path temporary_;
  std::ofstream stream_;
  bool committed_ = false;
  bool keep_ = false;
  bool append_ = false;
  int signal_slot_ = -1;  // the temporary, removed if SIGINT/SIGTERM ends the process
};

// A directory of outputs that appears whole or not at all (`owval pipeline`'s report; it too
// removes a killed process's temporary directory for the same destination): every file
// is written into a temporary sibling directory, and Commit() puts it in place of the destination,
// replacing an older one only then, so an interrupted rerun never mixes old and new artifacts. A
// destroyed AtomicDirectory that was never committed removes its temporary directory.
// It replaces only a directory that holds nothing or that owval wrote: the constructor (before
// any work) and Commit() refuse any other with InputError, so a user's own directory named as
// the output is never deleted.
class AtomicDirectory {
 public:
  // Replaces an empty directory or one an AtomicDirectory wrote (marked by DIR/.owval-directory).
  explicit AtomicDirectory(std::filesystem::path destination);
  // Replaces an empty directory or one `replaceable` accepts (e.g. an owval-written Zarr store);
  // writes no marker.
  AtomicDirectory(std::filesystem::path destination,
                  std::function<bool(const std::filesystem::path&)> replaceable);
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  // Where to write (created).
  const std::filesystem::path& temporary_path() const { return temporary_; }
  void Commit();

 private:
  // InputError unless the destination is missing, an empty directory or replaceable.
  void CheckReplaceable() const;

  std::filesystem::path destination_;
  std::filesystem::path temporary_;
  std::function<bool(const std::filesystem::path&)> replaceable_;
  bool committed_ = false;
  int signal_slot_ = -1;
};

// The marker of a directory an AtomicDirectory wrote (and may replace).
std::filesystem::path OwvalDirectoryMarker(const std::filesystem::path& directory);
// Writes that marker into `directory` (for an AtomicDirectory built with its own predicate).
void MarkOwvalDirectory(const std::filesystem::path& directory);

// Files (or directories) of one command that appear together or not at all, in one directory.
// Members are finished under temporary names first; Commit() then writes a marker, DIR/
// .owval-commit, naming them, removes older files of the same names (a directory only when the
// member is one too, which its writer checked it may replace; a directory in the way of a file is
// InputError before anything is removed), renames every member into
// place and removes the marker. A process stopped between those renames leaves the marker, and
// every owval reader refuses a file it names (RequireInputFile), so nothing ever reads a new file
// beside an old or missing sibling. A destroyed group that was never committed removes its
// members' temporaries.
class OutputGroup {
 public:
  OutputGroup() = default;
  ~OutputGroup();
  OutputGroup(const OutputGroup&) = delete;
  OutputGroup& operator=(const OutputGroup&) = delete;

  // Takes over a finished output (AtomicOutput::Release is called here).
  void Adopt(AtomicOutput* finished);
  // A temporary name beside `destination` for the caller to write (a file or a directory, by any
  // writer, itself atomic or not) that Commit() renames onto it.
  std::filesystem::path Stage(const std::filesystem::path& destination);
  // The temporary that will become `destination`; empty when it is not a member.
  std::filesystem::path TemporaryOf(const std::filesystem::path& destination) const;
  // An older output of the same command that this set replaces by nothing: Commit() removes it
  // with the older files of the members, under the same marker. A rerun that writes fewer files
  // than the run before it (a muscle log, then none) leaves no file from that run beside its own.
  // A directory is removed only when `is_ours` says it may be.
  void Retire(const std::filesystem::path& destination, bool is_ours = false);
  void Commit();

 private:
  struct Member {
    std::filesystem::path temporary, destination;  // temporary empty: retired, nothing renamed
    int signal_slot = -1;
  };
  std::vector<Member> members_;
  bool committed_ = false;
};

// Writes whole files of one directory as one OutputGroup: all appear, or none.
void WriteFilesTogether(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

// The marker an interrupted OutputGroup::Commit leaves in its directory.
std::filesystem::path CommitMarkerPath(const std::filesystem::path& directory);

// Makes SIGINT and SIGTERM remove the temporaries of every unfinished AtomicOutput,
// AtomicDirectory and OutputGroup, then end the process as the signal would (exit 130/143): a
// Ctrl-C during a render or a convert left ".out.mp4.tmp.PID.N" behind. The CLI calls it once at
// start; StopSignals (a run, a fit) takes the signals over while it exists.
void RemoveTemporariesOnSignal();

// Writes the whole string atomically. Also removes what a killed process left for the same
// destination (".NAME.tmp.PID.N" whose PID no longer runs). A streaming AtomicOutput does not:
// an interrupted run's checkpoint refers to its temporaries, and `owval run --resume` reopens them.
void WriteFileAtomically(const std::filesystem::path& destination, const std::string& contents);

// Checks, before any work starts, that `destination` can be written: not an existing directory,
// its parent directory exists (or can be created) and is writable. InputError naming the path.
// When directories must be made first, the error names the outermost of them (what the user
// typed: "/proc/x" of "/proc/x/position_buffer.txt") and what stops it.
void CheckOutputPath(const std::filesystem::path& destination);

// InputError naming `destination` when it exists as a device, FIFO or socket (through a symlink
// too): a rename over it replaces the node itself (as root, `--json-out /dev/full` left /dev/full
// a regular file holding the JSON). CheckOutputPath, AtomicOutput's constructor and every commit
// call it.
void RefuseSpecialFileOutput(const std::filesystem::path& destination);
// InputError naming `destination` when it is a symbolic link: the rename that commits an output
// replaces the link, not its target (`predict -o /dev/stdout` replaced the system's link with a
// regular file). CheckOutputPath and AtomicOutput's constructor call it.
void RefuseSymlinkOutput(const std::filesystem::path& destination);
// The same for a directory written whole (AtomicDirectory: a Zarr store, a report): not an
// existing file, and its parent (or nearest existing ancestor) takes new entries. InputError
// naming `directory`, or the outermost missing directory above it.
void CheckOutputDirectory(const std::filesystem::path& directory);
// InputError when `output` is one of `inputs`, through any spelling or link (fs::equivalent): a
// slip such as `compare a.h5 b.h5 --markdown b.h5` or `render a.h5 -o a.h5` replaced the input
// with the report. Empty or missing inputs are skipped.
void CheckOutputIsNotAnInput(const std::filesystem::path& output,
                             const std::vector<std::filesystem::path>& inputs);
// fs::create_directories, but InputError naming the outermost directory it could not create and
// why, instead of the library's "filesystem error: ..." line.
void CreateOutputDirectories(const std::filesystem::path& directory);

// The folders of an output directory that do not exist yet when a command starts (the directory
// and its missing parents). Destroyed before Keep(), e.g. by an exception, it removes those left
// empty, innermost first: a command that fails leaves no empty folder it made behind (the files
// it wrote there are its writers' to remove: AtomicOutput, OutputGroup).
class MissingDirectories {
 public:
  explicit MissingDirectories(const std::filesystem::path& directory);
  ~MissingDirectories();
  MissingDirectories(const MissingDirectories&) = delete;
  MissingDirectories& operator=(const MissingDirectories&) = delete;
  void Keep();

 private:
  std::vector<std::filesystem::path> missing_;  // innermost first
  std::vector<int> signal_slots_;               // removed, when left empty, on SIGINT/SIGTERM
  bool keep_ = false;
};

// A file a command makes for itself and removes (a benchmark's generated input): removed when
// destroyed, and when SIGINT or SIGTERM ends the process, whose default action skips destructors
// (a killed `owval bench io` left its 500 MB generated text behind). Keep() leaves it in place.
class ScratchFile {
 public:
  explicit ScratchFile(std::filesystem::path path);
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::filesystem::path& path() const { return path_; }
  void Keep();

 private:
  std::filesystem::path path_;
  int signal_slot_ = -1;
  bool keep_ = false;
};

// Reads a whole file; throws InputError naming the file when it is missing or unreadable.
std::string ReadWholeFile(const std::filesystem::path& path);

}  // namespace owval
