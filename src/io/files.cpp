#include "hydrolux/io/files.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <map>
#include <mutex>
#include <optional>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "hydrolux/core/error.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

namespace {

// ---- small helpers ----

std::string os_error(int err) { return std::generic_category().message(err); }

// How an error names a file: "-o out.png" with a label, "'out.png'" without.
std::string describe(std::string_view label, const fs::path& path) {
  return label.empty() ? fmt::format("'{}'", path.string()) : fmt::format("{} {}", label, path.string());
}

std::string file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

fs::path folder_of(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

// Where a dangling symbolic link points, for its message: " (to the missing X)"; empty if unreadable.
std::string dangling_target(const fs::path& link, std::string_view what) {
  std::error_code ec;
  const fs::path to = fs::read_symlink(link, ec);
  return ec ? std::string() : fmt::format(" (to the missing {} '{}')", what, to.string());
}

// Whether `p` is a symbolic link whose target does not exist.
bool dangling(const fs::path& p) {
  struct stat st {};
  if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return false;
  return ::stat(p.c_str(), &st) != 0 && errno == ENOENT;
}

// A hidden name beside `target` that no other writer uses: .<name>.tmp-<pid>-<n>. Long names are
// shortened so the temporary name stays within the 255-byte limit of common file systems.
fs::path temporary_sibling(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name = target.filename().string();
  if (name.size() > 200) name.resize(200);
  return folder_of(target) / fmt::format(".{}.tmp-{}-{}", name, ::getpid(), counter++);
}

int open_exclusive(const fs::path& p) {
  int fd;
  do fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOCTTY, 0666);
  while (fd < 0 && errno == EINTR);
  return fd;
}

// write(2) until every byte is out; returns 0 or the errno of the failure.
int write_all(int fd, std::string_view bytes) {
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, std::min<std::size_t>(left, std::size_t(1) << 30));
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) return EIO;
    p += n;
    left -= std::size_t(n);
  }
  return 0;
}

// fsync, tolerating file systems that cannot sync (EINVAL, EROFS on special files).
int sync_fd(int fd) {
  if (::fsync(fd) == 0) return 0;
  return (errno == EINVAL || errno == EROFS) ? 0 : errno;
}

void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);  // durability of the rename; a failure here cannot undo it
  ::close(fd);
}

// ---- the registry of pending temporary files and folders ----

struct Registry {
  std::mutex mutex;
  std::vector<std::pair<fs::path, bool /*folder*/>> pending;
  bool cancelled = false;
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: a cancelling thread may run during exit
  return *r;
}

// Creates a temporary file (or folder) and lists it, both under the registry's lock, so that a
// cancellation either sees it listed or stops it being created: none can appear after a cancel.
// Returns the new file's descriptor (0 for a folder), or -1 with errno set (ECANCELED once
// cancelled).
int create_tracked(const fs::path& p, bool folder) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  if (r.cancelled) {
    errno = ECANCELED;
    return -1;
  }
  const int fd = folder ? ::mkdir(p.c_str(), 0777) : open_exclusive(p);
  if (fd >= 0) r.pending.emplace_back(p, folder);
  return fd;
}

void untrack_locked(Registry& r, const fs::path& p) {
  r.pending.erase(std::remove_if(r.pending.begin(), r.pending.end(), [&](const auto& e) { return e.first == p; }),
                  r.pending.end());
}

void untrack(const fs::path& p) {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  untrack_locked(r, p);
}

// Checks the folder an output goes into: it exists, is a folder, and takes a new file (probed by
// creating and removing one, the only test that knows about read-only mounts, quotas and ACLs).
void probe_folder(const fs::path& target, std::string_view label) {
  const fs::path folder = folder_of(target);
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0)
    throw IoError(fmt::format("{}: the folder '{}' {}", describe(label, target), folder.string(),
                              errno == ENOENT ? std::string("does not exist") : os_error(errno)));
  if (!S_ISDIR(st.st_mode))
    throw IoError(fmt::format("{}: '{}' is not a folder", describe(label, target), folder.string()));
  const fs::path probe = temporary_sibling(target);
  const int fd = create_tracked(probe, false);
  if (fd < 0)
    throw IoError(fmt::format("{}: cannot create a file in the folder '{}': {}", describe(label, target),
                              folder.string(), os_error(errno)));
  ::close(fd);
  ::unlink(probe.c_str());
  untrack(probe);
}

}  // namespace

// ---- inputs ----

std::uint64_t check_input_file(const fs::path& path, std::string_view label) {
  if (path.empty()) throw IoError(fmt::format("{}: no file name given", label.empty() ? "input" : label));
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw IoError(fmt::format("{}: {}", describe(label, path),
                              errno == ENOENT ? std::string("no such file") : os_error(errno)));
  if (!S_ISREG(st.st_mode))
    throw IoError(fmt::format("{}: {}, not a regular file; give a file", describe(label, path), file_kind(st.st_mode)));
  return std::uint64_t(st.st_size);
}

std::string read_file(const fs::path& path, std::uint64_t max_bytes, std::string_view label) {
  const std::uint64_t size = check_input_file(path, label);
  if (size > max_bytes)
    throw IoError(fmt::format("{}: the file has {} bytes, more than the limit of {} bytes", describe(label, path),
                              size, max_bytes));
  // Non-blocking, so that a FIFO swapped in after the check cannot stall the open.
  int fd;
  do fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  while (fd < 0 && errno == EINTR);
  if (fd < 0) throw IoError(fmt::format("{}: cannot open: {}", describe(label, path), os_error(errno)));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || std::uint64_t(st.st_size) > max_bytes) {
    ::close(fd);
    throw IoError(fmt::format("{}: changed while being opened; not a regular file of at most {} bytes",
                              describe(label, path), max_bytes));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};  // also when allocating the buffer fails
  std::string bytes(std::size_t(st.st_size), '\0');
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoFailure(fmt::format("{}: read failed: {}", describe(label, path), os_error(errno)));
    }
    if (n == 0) break;  // the file shrank while being read: keep what is there
    got += std::size_t(n);
  }
  bytes.resize(got);
  return bytes;
}

InputFile::InputFile(const fs::path& path, std::string_view label) : path_(path), label_(label) {
  check_input_file(path, label);
  do fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  while (fd_ < 0 && errno == EINTR);
  if (fd_ < 0) throw IoError(fmt::format("{}: cannot open: {}", describe(label, path), os_error(errno)));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw IoError(fmt::format("{}: changed while being opened; not a regular file", describe(label, path)));
  }
  size_ = std::uint64_t(st.st_size);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t InputFile::read_at(std::uint64_t offset, char* buffer, std::size_t size) const {
  std::size_t got = 0;
  while (got < size) {
    const ssize_t n = ::pread(fd_, buffer + got, size - got, off_t(offset + got));
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoFailure(fmt::format("{}: read failed: {}", describe(label_, path_), os_error(errno)));
    }
    if (n == 0) break;
    got += std::size_t(n);
  }
  return got;
}

std::string lower_extension(const fs::path& path) {
  std::string e = path.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

bool same_file(const fs::path& a, const fs::path& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  std::error_code ea, eb;
  const auto ca = fs::weakly_canonical(fs::absolute(a, ea), ea);
  const auto cb = fs::weakly_canonical(fs::absolute(b, eb), eb);
  return !ea && !eb && ca == cb;
}

// ---- OutputFile ----

struct OutputFile::State {
  fs::path target, destination, temporary;
  std::string label;
  std::optional<mode_t> keep_mode;  // the replaced file's permissions
  int fd = -1;
  bool failed = false, committed = false;

  std::string name() const { return describe(label, target); }
  std::string outcome() const {
    return keep_mode ? fmt::format("{} is unchanged", destination.string()) : std::string("nothing was written");
  }
  // Removes the temporary file and throws IoFailure for an OS error `err` during `step`.
  [[noreturn]] void fail(const char* step, int err) {
    discard();
    failed = true;
    throw IoFailure(fmt::format("{}: {} failed: {}; {}, no partial file was left", name(), step, os_error(err),
                                outcome()));
  }
  void discard() noexcept {
    if (fd >= 0) ::close(fd);
    fd = -1;
    if (!temporary.empty()) {
      ::unlink(temporary.c_str());
      untrack(temporary);
      temporary.clear();
    }
  }
  void open_temporary() {
    for (int attempt = 0; attempt < 100; ++attempt) {
      temporary = temporary_sibling(destination);
      fd = create_tracked(temporary, false);
      if (fd >= 0) break;
      const int err = errno;
      temporary.clear();
      if (err != EEXIST) fail("creating the temporary file", err);
    }
    if (fd < 0) fail("creating the temporary file", EEXIST);
    if (keep_mode && ::fchmod(fd, *keep_mode) != 0) fail("setting permissions", errno);
  }
};

namespace {

// What an output path will replace: a symbolic link is written through, to the file it names (a
// dangling one is refused, as GNU cp refuses, since replacing the link would leave its real
// destination unwritten); an existing destination must be a regular file. Returns the destination
// and, if it exists, its permission bits. `name` is the path as the user gave it, with its label.
std::pair<fs::path, std::optional<mode_t>> output_destination(const fs::path& target, const std::string& name) {
  fs::path destination = target;
  struct stat st {};
  if (::lstat(target.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
    struct stat pointed {};
    if (::stat(target.c_str(), &pointed) != 0 && errno == ENOENT)
      throw IoError(fmt::format("{}: is a dangling symbolic link{}; give the file itself", name,
                                dangling_target(target, "file")));
    std::error_code ec;
    destination = fs::weakly_canonical(fs::absolute(target), ec);
    if (ec) throw IoError(fmt::format("{}: cannot resolve the symbolic link: {}", name, ec.message()));
  }
  if (::stat(destination.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw IoError(fmt::format("{}: is a folder; give a file name", name));
    if (!S_ISREG(st.st_mode))
      throw IoError(fmt::format("{}: is {}, not a regular file; refusing to replace it", name, file_kind(st.st_mode)));
    return {destination, mode_t(st.st_mode & 07777)};
  }
  if (errno != ENOENT) throw IoError(fmt::format("{}: {}", name, os_error(errno)));
  return {destination, std::nullopt};
}

}  // namespace

OutputFile::OutputFile(fs::path target, std::string label) : s_(std::make_unique<State>()) {
  s_->target = std::move(target);
  s_->label = std::move(label);
  if (s_->target.empty()) throw IoError(fmt::format("{}: no file name given", s_->label.empty() ? "output" : s_->label));
  const auto [destination, mode] = output_destination(s_->target, s_->name());
  s_->destination = destination;
  if (mode) s_->keep_mode = *mode;
  probe_folder(s_->destination, s_->label.empty() ? std::string_view{} : std::string_view(s_->label));
}

OutputFile::~OutputFile() {
  if (s_ && !s_->committed) s_->discard();
}
OutputFile::OutputFile(OutputFile&&) noexcept = default;
OutputFile& OutputFile::operator=(OutputFile&& other) noexcept {
  if (this != &other) {
    if (s_ && !s_->committed) s_->discard();
    s_ = std::move(other.s_);
  }
  return *this;
}

const fs::path& OutputFile::target() const { return s_->target; }
const fs::path& OutputFile::destination() const { return s_->destination; }
bool OutputFile::committed() const { return s_->committed; }

void OutputFile::write(std::string_view bytes) {
  if (s_->failed || s_->committed)
    throw IoFailure(fmt::format("{}: the output was already {}", s_->name(), s_->committed ? "committed" : "abandoned"));
  if (s_->fd < 0) s_->open_temporary();
  if (const int err = write_all(s_->fd, bytes)) s_->fail("writing", err);
}

void OutputFile::write_at(std::uint64_t offset, std::string_view bytes) {
  if (s_->failed || s_->committed)
    throw IoFailure(fmt::format("{}: the output was already {}", s_->name(), s_->committed ? "committed" : "abandoned"));
  if (s_->fd < 0) s_->open_temporary();
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::pwrite(s_->fd, bytes.data() + done, bytes.size() - done, off_t(offset + done));
    if (n < 0) {
      if (errno == EINTR) continue;
      s_->fail("writing", errno);
    }
    if (n == 0) s_->fail("writing", EIO);
    done += std::size_t(n);
  }
}

void OutputFile::commit() {
  if (s_->committed) return;
  write({});  // creates the (empty) temporary file if nothing was written
  if (const int err = sync_fd(s_->fd)) s_->fail("syncing to disk", err);
  const int fd = std::exchange(s_->fd, -1);
  if (::close(fd) != 0) s_->fail("closing", errno);
  {
    auto& r = registry();
    std::lock_guard lock(r.mutex);
    if (r.cancelled) {
      ::unlink(s_->temporary.c_str());
      untrack_locked(r, s_->temporary);
      s_->temporary.clear();
      s_->failed = true;
      throw IoFailure(fmt::format("{}: cancelled; {}", s_->name(), s_->outcome()));
    }
    if (::rename(s_->temporary.c_str(), s_->destination.c_str()) != 0) {
      const int err = errno;
      ::unlink(s_->temporary.c_str());
      untrack_locked(r, s_->temporary);
      s_->temporary.clear();
      s_->failed = true;
      throw IoFailure(fmt::format("{}: renaming into place failed: {}; {}, no partial file was left", s_->name(),
                                  os_error(err), s_->outcome()));
    }
    untrack_locked(r, s_->temporary);
    s_->temporary.clear();
    s_->committed = true;
  }
  sync_folder(folder_of(s_->destination));
}

void write_file(const fs::path& target, std::string_view bytes, std::string_view label) {
  OutputFile out(target, std::string(label));
  out.write(bytes);
  out.commit();
}

// ---- OutputDirectory ----

struct OutputDirectory::State {
  fs::path target, staging;
  std::string label;
  std::vector<std::string> files;
  std::vector<fs::path> protected_inputs;
  bool committed = false;

  std::string name() const { return describe(label, target); }
  void remove_staging() noexcept {
    if (staging.empty()) return;
    std::error_code ec;
    fs::remove_all(staging, ec);
    untrack(staging);
    staging.clear();
  }
};

OutputDirectory::OutputDirectory(fs::path target, std::string label) : s_(std::make_unique<State>()) {
  s_->target = std::move(target);
  s_->label = std::move(label);
  if (s_->target.empty() || s_->target.filename().empty()) {
    // "out/" names the folder "out": drop the trailing separator.
    if (!s_->target.empty() && s_->target.has_parent_path()) s_->target = s_->target.parent_path();
    if (s_->target.empty()) throw IoError(fmt::format("{}: no folder name given", s_->label.empty() ? "output" : s_->label));
  }
  struct stat st {};
  const bool exists = ::stat(s_->target.c_str(), &st) == 0;
  if (!exists && ::lstat(s_->target.c_str(), &st) == 0 && S_ISLNK(st.st_mode))
    throw IoError(fmt::format("{}: is a dangling symbolic link{}; give the folder itself", s_->name(),
                              dangling_target(s_->target, "folder")));
  if (exists && !S_ISDIR(st.st_mode))
    throw IoError(fmt::format("{}: is {}, not a folder", s_->name(), S_ISREG(st.st_mode) ? "a file" : file_kind(st.st_mode)));
  // A new folder is staged beside its destination and renamed into place whole. Into an existing
  // folder, the files are staged inside it: that proves now that it is writable, and the final
  // renames stay on its file system (it may be a mount point).
  const fs::path parent = exists ? s_->target : folder_of(s_->target);
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw IoError(fmt::format("{}: cannot create the folder '{}': {}", s_->name(), parent.string(), ec.message()));
  for (int attempt = 0; attempt < 100 && s_->staging.empty(); ++attempt) {
    const fs::path staging = temporary_sibling(exists ? s_->target / "hydrolux-staging" : s_->target);
    if (create_tracked(staging, true) == 0) {
      s_->staging = staging;
    } else {
      const int err = errno;
      if (err != EEXIST)
        throw IoError(fmt::format("{}: cannot create a folder in '{}': {}", s_->name(), parent.string(), os_error(err)));
    }
  }
  if (s_->staging.empty()) throw IoError(fmt::format("{}: cannot create a staging folder", s_->name()));
}

OutputDirectory::~OutputDirectory() {
  if (s_ && !s_->committed) s_->remove_staging();
}

const fs::path& OutputDirectory::target() const { return s_->target; }
const std::vector<std::string>& OutputDirectory::files() const { return s_->files; }
bool OutputDirectory::committed() const { return s_->committed; }
void OutputDirectory::protect(std::vector<fs::path> inputs) { s_->protected_inputs = std::move(inputs); }

void OutputDirectory::write(const std::string& name, std::string_view bytes) {
  // A plain name, or one subfolder and a plain name ("glsl/sky.glsl").
  const auto plain = [](std::string_view n) {
    return !n.empty() && n != "." && n != ".." && n.find('/') == std::string_view::npos;
  };
  const auto slash = name.find('/');
  const std::string sub = slash == std::string::npos ? std::string() : name.substr(0, slash);
  if (slash == std::string::npos ? !plain(name) : !(plain(sub) && plain(std::string_view(name).substr(slash + 1))))
    throw IoError(fmt::format("{}: '{}' is not a plain file name (or one subfolder and a file name)", s_->name(), name));
  if (s_->committed || s_->staging.empty()) throw IoFailure(fmt::format("{}: the folder was already committed", s_->name()));
  if (!sub.empty()) {
    std::error_code ec;
    fs::create_directory(s_->staging / sub, ec);
    if (ec)
      throw IoFailure(fmt::format("{}: creating the subfolder {} failed: {}; {} is unchanged", s_->name(), sub,
                                  ec.message(), s_->target.string()));
  }
  const fs::path file = s_->staging / name;
  int fd;
  {
    // Under the registry's lock: a cancellation removing the staging folder never races a file
    // being created in it.
    auto& r = registry();
    std::lock_guard lock(r.mutex);
    if (r.cancelled) {
      fd = -1;
      errno = ECANCELED;
    } else {
      do fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOCTTY, 0666);
      while (fd < 0 && errno == EINTR);
    }
  }
  int err = fd < 0 ? errno : write_all(fd, bytes);
  if (!err) err = sync_fd(fd);
  if (fd >= 0 && ::close(fd) != 0 && !err) err = errno;
  if (err)
    throw IoFailure(fmt::format("{}: writing {} failed: {}; {} is unchanged, no partial file was left", s_->name(),
                                name, os_error(err), s_->target.string()));
  if (std::find(s_->files.begin(), s_->files.end(), name) == s_->files.end()) s_->files.push_back(name);
}

void OutputDirectory::commit() {
  if (s_->committed) return;
  struct stat st {};
  const bool exists = ::stat(s_->target.c_str(), &st) == 0;
  if (!exists && ::lstat(s_->target.c_str(), &st) == 0 && S_ISLNK(st.st_mode))
    throw IoError(fmt::format("{}: is a dangling symbolic link{}; give the folder itself", s_->name(),
                              dangling_target(s_->target, "folder")));
  if (exists && !S_ISDIR(st.st_mode)) throw IoError(fmt::format("{}: is no longer a folder", s_->name()));
  if (exists)
    for (const auto& f : s_->files)
      for (const auto& in : s_->protected_inputs)
        if (same_file(s_->target / f, in))
          throw IoError(fmt::format("{}: {} would replace the input {}", s_->name(), f, in.string()));
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  if (r.cancelled) throw IoFailure(fmt::format("{}: cancelled; {} is unchanged", s_->name(), s_->target.string()));
  if (!exists) {
    if (::rename(s_->staging.c_str(), s_->target.c_str()) != 0)
      throw IoFailure(fmt::format("{}: moving the finished folder into place failed: {}", s_->name(), os_error(errno)));
  } else {
    // A file cannot replace a folder, nor a subfolder a file: refused before anything moves, so no
    // mix is left.
    std::vector<std::string> subs;
    for (const auto& f : s_->files) {
      struct stat dst {};
      if (::lstat((s_->target / f).c_str(), &dst) == 0 && S_ISDIR(dst.st_mode))
        throw IoError(fmt::format("{}: {} is a folder and cannot be replaced by a file; nothing was replaced",
                                  s_->name(), f));
      const auto slash = f.find('/');
      if (slash == std::string::npos) continue;
      const std::string sub = f.substr(0, slash);
      if (std::find(subs.begin(), subs.end(), sub) == subs.end()) subs.push_back(sub);
      struct stat sd {};
      if (::lstat((s_->target / sub).c_str(), &sd) == 0 && !S_ISDIR(sd.st_mode))
        throw IoError(fmt::format("{}: {} is a file and cannot become a folder; nothing was replaced", s_->name(), sub));
    }
    for (const auto& sub : subs)
      if (::mkdir((s_->target / sub).c_str(), 0777) != 0 && errno != EEXIST)
        throw IoFailure(fmt::format("{}: creating {} failed: {}", s_->name(), sub, os_error(errno)));
    std::size_t moved = 0;
    for (const auto& f : s_->files) {
      if (::rename((s_->staging / f).c_str(), (s_->target / f).c_str()) != 0)
        throw IoFailure(fmt::format("{}: moving {} into place failed: {} ({} of {} files replaced)", s_->name(), f,
                                    os_error(errno), moved, s_->files.size()));
      ++moved;
    }
    for (const auto& sub : subs) ::rmdir((s_->staging / sub).c_str());
    ::rmdir(s_->staging.c_str());
  }
  untrack_locked(r, s_->staging);
  s_->staging.clear();
  s_->committed = true;
  sync_folder(s_->target);
  sync_folder(folder_of(s_->target));
}

// ---- FileSet ----

struct FileSet::State {
  struct Named {
    std::string label;
    fs::path path;
  };
  // What same_file() compares, computed once a file: its device and inode where it exists, and its
  // absolute path with links, "." and ".." resolved. Looked up in hash tables, so that declaring the
  // thousands of members of a folder run costs O(n), not a same_file() per pair.
  struct Key {
    std::optional<std::pair<dev_t, ino_t>> inode;
    std::string path;  // empty if it cannot be resolved (then only the inode counts)
  };
  struct Index {
    std::map<std::pair<dev_t, ino_t>, std::size_t> by_inode;
    std::unordered_map<std::string, std::size_t> by_path, by_path_without_inode;
    void add(const Key& k, std::size_t i) {
      if (k.inode) by_inode.emplace(*k.inode, i);
      if (!k.path.empty()) {
        by_path.emplace(k.path, i);
        if (!k.inode) by_path_without_inode.emplace(k.path, i);
      }
    }
    // same_file(): the same inode where both exist, else the same resolved path.
    std::optional<std::size_t> find(const Key& k) const {
      if (k.inode) {
        if (const auto it = by_inode.find(*k.inode); it != by_inode.end()) return it->second;
        if (k.path.empty()) return std::nullopt;
        if (const auto it = by_path_without_inode.find(k.path); it != by_path_without_inode.end()) return it->second;
        return std::nullopt;
      }
      if (k.path.empty()) return std::nullopt;
      if (const auto it = by_path.find(k.path); it != by_path.end()) return it->second;
      return std::nullopt;
    }
  };
  static Key key_of(const fs::path& p) {
    Key k;
    struct stat st {};
    if (::stat(p.c_str(), &st) == 0) k.inode = std::pair{st.st_dev, st.st_ino};
    std::error_code ec;
    const auto canonical = fs::weakly_canonical(fs::absolute(p, ec), ec);
    if (!ec) k.path = canonical.string();
    return k;
  }

  std::vector<Named> inputs;
  std::vector<Named> output_names;
  Index input_index, output_index;
  std::vector<std::unique_ptr<OutputFile>> files;
  std::vector<std::unique_ptr<OutputDirectory>> folders;
  std::vector<std::pair<bool /*folder*/, std::size_t>> order;

  // Refuses an output on an input or another output; returns its key for add_output().
  Key refuse_clash(const std::string& label, const fs::path& path) const {
    Key k = key_of(path);
    if (const auto i = input_index.find(k)) {
      const Named& in = inputs[*i];
      throw IoError(fmt::format("{} {}: is the same file as the input {} {}; refusing to overwrite an input", label,
                                path.string(), in.label, in.path.string()));
    }
    if (const auto o = output_index.find(k)) {
      const Named& out = output_names[*o];
      throw IoError(fmt::format("{} {}: is the same file as the output {} {}", label, path.string(), out.label,
                                out.path.string()));
    }
    return k;
  }
  void add_output(const Key& k, std::string label, fs::path path) {
    output_index.add(k, output_names.size());
    output_names.push_back({std::move(label), std::move(path)});
  }
};

FileSet::FileSet() : s_(std::make_unique<State>()) {}
FileSet::~FileSet() = default;

std::uint64_t FileSet::input(std::string label, fs::path path) {
  const auto size = check_input_file(path, label);
  const State::Key k = State::key_of(path);
  if (const auto o = s_->output_index.find(k)) {
    const State::Named& out = s_->output_names[*o];
    throw IoError(fmt::format("{} {}: is the same file as the output {} {}; refusing to overwrite an input", label,
                              path.string(), out.label, out.path.string()));
  }
  s_->input_index.add(k, s_->inputs.size());
  s_->inputs.push_back({std::move(label), std::move(path)});
  return size;
}

OutputFile& FileSet::output(std::string label, fs::path path) {
  const State::Key k = s_->refuse_clash(label, path);
  auto out = std::make_unique<OutputFile>(path, label);
  s_->add_output(k, std::move(label), std::move(path));
  s_->files.push_back(std::move(out));
  s_->order.emplace_back(false, s_->files.size() - 1);
  return *s_->files.back();
}

void FileSet::planned_output(std::string label, fs::path path) {
  // Its folder is created later (create_directories would fail on a dangling link with "File
  // exists"): a folder that is a dangling symbolic link is refused now, by its label.
  for (fs::path folder = path.parent_path(); !folder.empty() && folder != folder.root_path();
       folder = folder.parent_path()) {
    if (dangling(folder))
      throw IoError(fmt::format("{} {}: is a dangling symbolic link{}; give a folder, or create its target", label,
                                folder.string(), dangling_target(folder, "folder")));
    if (folder == folder.parent_path()) break;
  }
  const State::Key k = s_->refuse_clash(label, path);
  output_destination(path, describe(label, path));
  s_->add_output(k, std::move(label), std::move(path));
}

OutputDirectory& FileSet::output_directory(std::string label, fs::path path) {
  for (const auto& in : s_->inputs)
    if (same_file(in.path, path))
      throw IoError(fmt::format("{} {}: is the input {}", label, path.string(), in.label));
  auto out = std::make_unique<OutputDirectory>(path, label);
  std::vector<fs::path> inputs;
  for (const auto& in : s_->inputs) inputs.push_back(in.path);
  out->protect(std::move(inputs));
  s_->add_output(State::key_of(path), std::move(label), std::move(path));
  s_->folders.push_back(std::move(out));
  s_->order.emplace_back(true, s_->folders.size() - 1);
  return *s_->folders.back();
}

void FileSet::commit() {
  for (const auto& [folder, i] : s_->order) {
    if (folder)
      s_->folders[i]->commit();
    else
      s_->files[i]->commit();
  }
}

// ---- cancellation ----

std::size_t cancel_pending_outputs() noexcept {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  r.cancelled = true;
  std::size_t n = 0;
  for (const auto& [path, folder] : r.pending) {
    std::error_code ec;
    if (folder)
      fs::remove_all(path, ec);
    else
      ::unlink(path.c_str());
    ++n;
  }
  r.pending.clear();
  return n;
}

std::size_t pending_output_count() noexcept {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  return r.pending.size();
}

}  // namespace hydrolux::io
