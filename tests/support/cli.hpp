#pragma once
// Running the built hydrolux CLI from a test: its exit code, stdout and stderr; and the usage-error
// contract (exit code 2, one line on stderr naming the flag, nothing on stdout). Header-only: the
// CLI's path comes from each test executable's HYDROLUX_CLI_PATH definition.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

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

inline std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

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
  fs::create_directories(d);
  return d;
}

}  // namespace hydrolux::testing
