#pragma once
// Running the built hydrolux CLI from a test: its exit code, stdout and stderr; and the usage-error
// contract (exit code 2, one line on stderr naming the flag, nothing on stdout). Header-only: the
// CLI's path comes from each test executable's HYDROLUX_CLI_PATH definition.
//   run("args")            through the shell (quoting as in a terminal)
//   run_argv({...}, hook)  without a shell, each argument as given; `hook` runs in the child just
//                          before exec (set a resource limit, ...): only async-signal-safe calls
//   spawn / finish         the same, started in the background (to signal it meanwhile)
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstdint>
#include <csignal>
#include <functional>
#include <mutex>
#include <set>
#include <vector>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

namespace hydrolux::testing {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string out, err;
  std::uint64_t peak_rss_bytes = 0;  // the process's peak resident size (run_argv only; getrusage's maxrss)
};

inline Result run(const std::string& args) {
  const fs::path err_file = fs::temp_directory_path() / ("hydrolux_cli_err_" + std::to_string(::getpid()));
  const std::string cmd = std::string(HYDROLUX_CLI_PATH) + " " + args + " 2>" + err_file.string();
  Result r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  fs::remove(err_file);
  return r;
}

// A whole file's bytes ("" if it cannot be read).
inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

// ffprobe's width, height, frame rate and decoded frame count of a video's first stream, as one CSV
// line ("64,48,25/1,5\n"; "" without ffprobe or a video stream).
inline std::string ffprobe_csv(const fs::path& f) {
  const std::string cmd = "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                          "stream=nb_read_frames,r_frame_rate,width,height -of csv=p=0 '" + f.string() + "'";
  std::string s;
  FILE* p = ::popen(cmd.c_str(), "r");
  char buf[256];
  while (p && std::fgets(buf, sizeof buf, p)) s += buf;
  if (p) ::pclose(p);
  return s;
}

// Bad input: exit code 2, exactly one line on stderr that names the flag, nothing on stdout. `cases`
// is any range of (arguments, text the error must contain) pairs.
template <typename Cases>
void expect_usage_errors(const Cases& cases) {
  for (const auto& [args, flag] : cases) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(lines(r.err), 1u) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
  }
}

// A fresh directory under the system's temporary directory, unique to this process.
inline fs::path temp_dir(const std::string& prefix) {
  const fs::path d = fs::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()));
  // Emptied the first time this process asks for it: a folder left by an earlier process that had
  // the same id (ids are reused on a long-lived machine) would otherwise hold its files.
  static std::mutex m;
  static std::set<std::string> emptied;
  {
    std::lock_guard lock(m);
    if (emptied.insert(prefix).second) fs::remove_all(d);
  }
  fs::create_directories(d);
  return d;
}

// The built-in street scene, clear (no rain), written by the CLI to `file` (.exr or .png) at `size`
// ("WxH"); a test keeps the path in a function-local static so that it is made once.
inline fs::path builtin_frame(const fs::path& file, const std::string& size) {
  const Result r = run("rain -q --image builtin --size " + size + " --rain-rate-mmh 0 -o " + file.string());
  EXPECT_EQ(r.code, 0) << r.err;
  return file;
}

// A CLI process started in the background; its stdout and stderr go to files.
struct Process {
  pid_t pid = -1;
  fs::path out_file, err_file;
};

inline Process spawn(const std::vector<std::string>& args, const std::function<void()>& hook = {}) {
  static std::atomic<unsigned> counter{0};
  const auto stem = fs::temp_directory_path() /
                    ("hydrolux_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  Process p{-1, stem.string() + ".out", stem.string() + ".err"};
  std::vector<std::string> argv_text{HYDROLUX_CLI_PATH};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string out = p.out_file.string(), err = p.err_file.string();
  p.pid = ::fork();
  if (p.pid == 0) {
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    const int in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    if (o < 0 || e < 0 || in < 0) ::_exit(126);
    ::dup2(in, 0);
    ::dup2(o, 1);
    ::dup2(e, 2);
    if (hook) hook();
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return p;
}

// Whether the process is still running, without reaping it (finish() collects its status).
inline bool still_running(const Process& p) {
  siginfo_t info{};
  if (::waitid(P_PID, id_t(p.pid), &info, WEXITED | WNOHANG | WNOWAIT) != 0) return false;
  return info.si_pid == 0;
}

// A hang detector, not a time limit: a CLI run that has not ended after this long is stuck (a
// read blocking on a FIFO, a loop that never ends); it is killed and the test fails saying so,
// instead of the whole suite hanging until CI gives up. Every run in these tests takes seconds.
inline constexpr int kHungAfterSeconds = 600;

// Waits for the process; the exit code, or 128 + the signal that ended it. A process still running
// after kHungAfterSeconds is killed: code -2 and a note in `err`.
inline Result finish(const Process& p) {
  Result r;
  int status = 0;
  bool hung = false, lost = false;
  rusage usage{};
  const auto start = std::chrono::steady_clock::now();
  while (true) {
    const pid_t done = ::wait4(p.pid, &status, WNOHANG, &usage);
    if (done == p.pid) break;
    if (done < 0 && errno != EINTR) {  // not our child (ECHILD): nothing to wait for
      lost = true;
      break;
    }
    if (!hung && std::chrono::steady_clock::now() - start > std::chrono::seconds(kHungAfterSeconds)) {
      hung = true;
      ::kill(p.pid, SIGKILL);
    }
    ::usleep(5000);
  }
  r.code = lost ? -1 : hung ? -2 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.peak_rss_bytes = std::uint64_t(usage.ru_maxrss) * 1024;
  const auto slurp = [](const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(p.out_file);
  r.err = slurp(p.err_file);
  if (hung) r.err += "[hung: killed by the test after " + std::to_string(kHungAfterSeconds) + " s]\n";
  fs::remove(p.out_file);
  fs::remove(p.err_file);
  return r;
}

inline Result run_argv(const std::vector<std::string>& args, const std::function<void()>& hook = {}) {
  return finish(spawn(args, hook));
}

}  // namespace hydrolux::testing
