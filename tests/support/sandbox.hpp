#pragma once
// Making file-system failures happen on purpose, for the tests of the safe output path:
//   - run_in_child: runs a function in a forked child and returns its exit code, so that a test
//     can set a process limit (a file-size limit makes writes fail with EFBIG), cancel the
//     process-wide output registry, or change mounts without touching the test process;
//   - enter_private_mounts: in such a child, a private mount namespace (as root, or through a user
//     namespace otherwise) in which a tiny tmpfs is a real full disk (ENOSPC) and a read-only
//     mount a real unwritable folder (EROFS) even for root.
// Header-only; Linux.
#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

namespace hydrolux::testing {

// Exit codes of a child that could not set up what it needed (the test skips).
inline constexpr int kChildCannotSetUp = 77;

inline int run_in_child(const std::function<int()>& body) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    int code = 1;
    try {
      code = body();
    } catch (...) {
      code = 99;
    }
    std::fflush(nullptr);
    ::_exit(code);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

inline bool write_proc_file(const char* path, const std::string& text) {
  const int fd = ::open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::write(fd, text.data(), text.size()) == ssize_t(text.size());
  ::close(fd);
  return ok;
}

// In a forked child: a private mount namespace. Returns false if the system allows none.
inline bool enter_private_mounts() {
  const uid_t uid = ::geteuid();
  const gid_t gid = ::getegid();
  if (::unshare(CLONE_NEWNS) != 0) {
    if (::unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0) return false;
    (void)write_proc_file("/proc/self/setgroups", "deny");
    if (!write_proc_file("/proc/self/uid_map", "0 " + std::to_string(uid) + " 1\n")) return false;
    if (!write_proc_file("/proc/self/gid_map", "0 " + std::to_string(gid) + " 1\n")) return false;
  }
  // Mounts made here must not propagate to the test's own namespace.
  return ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) == 0;
}

// A tmpfs of `kib` KiB over `dir` (which must exist), read-only if asked.
inline bool mount_tmpfs(const std::string& dir, int kib, bool read_only = false) {
  const std::string options = "size=" + std::to_string(kib) + "k";
  return ::mount("tmpfs", dir.c_str(), "tmpfs", read_only ? MS_RDONLY : 0, options.c_str()) == 0;
}

// Fills the file system holding `dir` until a write fails with ENOSPC.
inline void fill_up(const std::string& dir) {
  std::ofstream f(dir + "/filler", std::ios::binary);
  const std::string block(4096, 'x');
  for (int i = 0; i < 1 << 20 && f.write(block.data(), block.size()); ++i) {
  }
  f.close();
  std::ofstream g(dir + "/filler2", std::ios::binary);  // the last partial block
  for (int i = 0; i < 4096 && g.put('x'); ++i) {
  }
}

}  // namespace hydrolux::testing
