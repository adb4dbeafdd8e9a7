#pragma once
// The one path through which hydrolux reads and writes files. Every command, the gallery and the
// library's own writers use it, so each promise below is kept once, here, and tested once
// (tests/io/test_files.cpp, tests/cli/test_robustness.cpp).
//
// Inputs
//   Only regular files are read. A FIFO, a device, a socket or a directory is refused from its
//   stat() before it is opened, so nothing blocks on it, and the file is opened non-blocking and
//   checked again on the open descriptor. A size limit is checked before anything is read.
//
// Outputs
//   Nothing is written in place. An output is reserved before the work starts: its folder must
//   exist and accept a new file (probed by creating one), an existing target must be a regular
//   file, and it must not be the same file as any input (FileSet). At the end its bytes go to a
//   hidden temporary file beside it (.<name>.tmp-<pid>-<n>); every write is checked, the file is
//   synced to disk and closed, and only then renamed over the target, whose old permissions it
//   keeps. On any failure the target is untouched and the temporary file removed. A folder of
//   outputs (the gallery) is written into a hidden temporary folder beside its destination and
//   moved into place when complete.
//
// Cancellation
//   Pending temporary files and folders are listed in a process-wide registry. A program that
//   handles SIGINT/SIGTERM calls cancel_pending_outputs() from an ordinary thread (the CLI waits
//   for signals with sigwait); it removes them all and blocks any later commit.
//
// Errors name the path (and the caller's label for it, e.g. a flag): IoError for a file that
// cannot be used (found before any output is replaced), IoFailure for an operation the system
// failed midway (a full disk), with the OS's reason.
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace hydrolux::io {

// ---- inputs ---------------------------------------------------------------------------------

// The default size limit of a file read whole (4 GiB).
inline constexpr std::uint64_t kMaxInputBytes = std::uint64_t(4) << 30;

// Checks that `path` names a regular file (through symbolic links) and returns its size in bytes.
// Throws IoError naming the path, prefixed by `label` if given ("--env"), when it is missing, a
// directory, a FIFO, a device or a socket.
std::uint64_t check_input_file(const std::filesystem::path& path, std::string_view label = {});

// Reads a whole regular file of at most `max_bytes`. Throws IoError (as check_input_file, or an
// unreadable or too large file) or IoFailure (a read error midway).
std::string read_file(const std::filesystem::path& path, std::uint64_t max_bytes = kMaxInputBytes,
                      std::string_view label = {});

// A regular file opened for reading in pieces at any offset, for inputs too large to read whole
// (video). Opened as read_file opens (checked by stat, opened non-blocking, checked again on the
// descriptor). IoError as check_input_file; IoFailure for a read error midway.
class InputFile {
 public:
  explicit InputFile(const std::filesystem::path& path, std::string_view label = {});
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  std::uint64_t size() const { return size_; }
  const std::filesystem::path& path() const { return path_; }
  // Reads up to `size` bytes at `offset` into `buffer`; returns how many (fewer only at the end of
  // the file, 0 at or past it).
  std::size_t read_at(std::uint64_t offset, char* buffer, std::size_t size) const;

 private:
  std::filesystem::path path_;
  std::string label_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

// The extension of `path` in lower case, with its dot (".exr"); empty if none.
std::string lower_extension(const std::filesystem::path& path);

// True if `a` and `b` name the same existing file (same device and inode, through links), or
// resolve to the same absolute path once symbolic links and "..", "." are resolved.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

// ---- outputs --------------------------------------------------------------------------------

// One output file, written whole at the end and renamed into place (see the top of this file).
class OutputFile {
 public:
  // Reserves `target` now: IoError if its folder does not exist or cannot take a new file, or if
  // the target exists and is not a regular file. A symbolic link is followed: the file it points
  // to is replaced, the link kept. `label` prefixes error messages (e.g. "-o").
  explicit OutputFile(std::filesystem::path target, std::string label = {});
  ~OutputFile();  // removes the temporary file unless committed
  OutputFile(OutputFile&&) noexcept;
  OutputFile& operator=(OutputFile&&) noexcept;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // The path as given, and the file that will be replaced (symbolic links resolved).
  const std::filesystem::path& target() const;
  const std::filesystem::path& destination() const;

  // Appends bytes to the temporary file (created on the first call). IoFailure on any error; the
  // temporary file is then removed and the output can no longer be committed.
  void write(std::string_view bytes);
  // Writes bytes at `offset` of the temporary file (for container formats that go back to fill in
  // an index, e.g. MP4); the same failures as write(). write() goes on where the last write() ended.
  void write_at(std::uint64_t offset, std::string_view bytes);
  // Syncs, closes and renames the temporary file over the destination. IoFailure on error (the
  // destination is then untouched), or if cancel_pending_outputs() was called.
  void commit();
  bool committed() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// Writes `bytes` to `target` through an OutputFile: all or nothing.
void write_file(const std::filesystem::path& target, std::string_view bytes, std::string_view label = {});

// A folder of outputs, staged in a hidden temporary folder beside the destination and moved into
// place by commit(): renamed as a whole if the destination does not exist; otherwise each staged
// file replaces its namesake (files of other names in the destination are kept).
class OutputDirectory {
 public:
  // Creates missing parent folders and the staging folder now: IoError if that fails or the
  // destination exists and is not a folder.
  explicit OutputDirectory(std::filesystem::path target, std::string label = {});
  ~OutputDirectory();  // removes the staging folder unless committed
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  const std::filesystem::path& target() const;
  // Writes one file into the staging folder, synced: a plain name, or one subfolder and a plain name
  // ("glsl/sky.glsl"; the subfolder is created). IoFailure on error.
  void write(const std::string& name, std::string_view bytes);
  // The names written so far, in order.
  const std::vector<std::string>& files() const;
  // Files that commit() must never replace (the run's inputs): IoError at commit if a staged file
  // would.
  void protect(std::vector<std::filesystem::path> inputs);
  void commit();
  bool committed() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// The files of one run: its inputs and its outputs, each with a label naming it in errors (a
// flag such as "--env"). Declaring a file checks it at once: an input must be a regular file; an
// output is reserved (OutputFile) and refused if it is the same file as an input or another
// output, whichever was declared first. Commands declare every file before they start work, so
// a bad path fails in a second, not after a long render; a command that reads or writes folders
// declares each member it reads (input) and each it will write (planned_output), so that no output,
// in a folder or not, can land on an input or on another output.
class FileSet {
 public:
  FileSet();
  ~FileSet();
  FileSet(const FileSet&) = delete;
  FileSet& operator=(const FileSet&) = delete;

  // Returns the input's size in bytes.
  std::uint64_t input(std::string label, std::filesystem::path path);
  OutputFile& output(std::string label, std::filesystem::path path);
  // An output the command writes later through write_file() (one file of a folder of outputs, such
  // as a rainy frame): checked now as output() checks it (not an input, not another output, not a
  // folder or a device), without reserving it, since its folder may not exist yet.
  void planned_output(std::string label, std::filesystem::path path);
  OutputDirectory& output_directory(std::string label, std::filesystem::path path);
  // Commits every output in the order declared.
  void commit();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// ---- cancellation ---------------------------------------------------------------------------

// Removes every pending temporary file and staging folder of this process and makes every later
// commit() fail. Takes a lock, so call it from an ordinary thread (e.g. one waiting in sigwait),
// never from a signal handler. Returns how many were removed.
std::size_t cancel_pending_outputs() noexcept;

// The number of pending temporary files and staging folders (for tests).
std::size_t pending_output_count() noexcept;

}  // namespace hydrolux::io
