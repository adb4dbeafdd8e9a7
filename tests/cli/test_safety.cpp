// The CLI never loses or corrupts a file (issue #9), end to end, each defect reproduced:
//   - an output that is an input (by the same name, a link or a hard link) is refused, exit 2;
//   - a missing or read-only output folder is found before the work starts, naming the user's path;
//   - a full disk (a real one: a filled 64 KiB tmpfs) and a file-size limit fail with exit 1 and one
//     line naming the path and the OS error; the old file is untouched and no temporary file is left;
//   - Ctrl-C and SIGTERM remove what a run had pending and exit 130 and 143; an interrupted gallery
//     leaves the old gallery as it was;
//   - the same inputs give the same EXR, PNG and JSON bytes.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "hydrolux/io/image_io.hpp"
#include "support/cli.hpp"
#include "support/sandbox.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::finish;
using hydrolux::testing::lines;
using hydrolux::testing::run_argv;
using hydrolux::testing::spawn;

using hydrolux::testing::slurp;

std::vector<std::string> listing(const fs::path& d) {
  std::vector<std::string> n;
  for (const auto& e : fs::directory_iterator(d)) n.push_back(e.path().filename().string());
  std::sort(n.begin(), n.end());
  return n;
}

class Safety : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hydrolux_safety_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A small drop picture and a small environment map to use as inputs.
  fs::path drop_png() {
    const fs::path p = dir_ / "drop.png";
    const auto r = run_argv({"drop", "render", "-q", "--size", "32", "--samples", "1", "-o", p.string()});
    EXPECT_EQ(r.code, 0) << r.err;
    return p;
  }
  fs::path dir_;
};

// `drop undistort -o X --image X` and `drop render -o X --env X` used to overwrite their input.
TEST_F(Safety, OutputThatIsAnInputIsRefused) {
  const fs::path png = drop_png();
  const std::string before = slurp(png);
  fs::create_symlink(png, dir_ / "link.png");
  fs::create_hard_link(png, dir_ / "hard.png");
  for (const fs::path& out : {png, dir_ / "link.png", dir_ / "hard.png", dir_ / "." / "drop.png"}) {
    const auto r = run_argv({"drop", "undistort", "--image", png.string(), "--drop-center", "16,16",
                             "--drop-radius-px", "5", "-o", out.string()});
    EXPECT_EQ(r.code, 2) << out;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("-o " + out.string() + ": is the same file as the input --image"), std::string::npos)
        << r.err;
  }
  EXPECT_EQ(slurp(png), before);
  const fs::path env = dir_ / "env.exr";
  ASSERT_EQ(run_argv({"drop", "render", "-q", "--size", "16", "--samples", "1", "--no-background", "-o",
                      (dir_ / "tmp.exr").string()})
                .code,
            0);
  fs::rename(dir_ / "tmp.exr", env);  // 16 x 16 is not 2:1, but the check comes before reading it
  const std::string env_before = slurp(env);
  const auto r = run_argv({"drop", "render", "--env", env.string(), "-o", env.string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is the same file as the input --env"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(env), env_before);
}

// A missing or unwritable output folder is reported at once, naming the path given: the render
// asked for here (16384 x 16384 pixels, 64 x 64 samples each) would run for days if it started.
TEST_F(Safety, OutputFolderIsCheckedBeforeTheWork) {
  const std::vector<std::string> huge = {"drop", "render", "--size", "16384", "--samples", "64", "-o"};
  auto args = huge;
  args.push_back((dir_ / "missing" / "x.png").string());
  auto r = run_argv(args);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("-o " + (dir_ / "missing" / "x.png").string() + ": the folder"), std::string::npos) << r.err;
  const std::string ro = (dir_ / "ro").string();
  fs::create_directories(ro);
  args = huge;
  args.push_back(ro + "/x.png");
  const int code = hydrolux::testing::run_in_child([&] {
    if (!hydrolux::testing::enter_private_mounts() || !hydrolux::testing::mount_tmpfs(ro, 64, true))
      return hydrolux::testing::kChildCannotSetUp;
    const auto res = run_argv(args);
    if (res.code != 2 || lines(res.err) != 1) return 1;
    if (res.err.find("-o " + ro + "/x.png: cannot create a file in the folder") == std::string::npos) return 2;
    if (res.err.find("Read-only file system") == std::string::npos) return 3;
    return res.err.find(".tmp-") == std::string::npos ? 0 : 4;  // never a temporary name
  });
  if (code == hydrolux::testing::kChildCannotSetUp) GTEST_SKIP() << "no private mount namespace here";
  EXPECT_EQ(code, 0);
}

// A full disk: a 64 KiB tmpfs, filled, then a render whose PNG does not fit. Before, the PNG was
// truncated, the exit code 0 and the old file already replaced.
TEST_F(Safety, FullDiskFailsWithExitOneAndKeepsTheOldFile) {
  const std::string mnt = (dir_ / "mnt").string();
  fs::create_directories(mnt);
  const int code = hydrolux::testing::run_in_child([&] {
    if (!hydrolux::testing::enter_private_mounts() || !hydrolux::testing::mount_tmpfs(mnt, 64))
      return hydrolux::testing::kChildCannotSetUp;
    { std::ofstream(mnt + "/out.png") << "the old picture"; }
    hydrolux::testing::fill_up(mnt);
    const auto before = listing(mnt);
    const auto res = run_argv({"drop", "render", "-q", "--size", "256", "--samples", "1", "-o", mnt + "/out.png"});
    if (res.code != 1) return 10 + std::min(res.code, 50);
    if (lines(res.err) != 1) return 2;
    if (res.err.find("-o " + mnt + "/out.png: writing failed: No space left on device") == std::string::npos) return 3;
    if (slurp(mnt + "/out.png") != "the old picture") return 4;
    return listing(mnt) == before ? 0 : 5;  // no temporary file left
  });
  if (code == hydrolux::testing::kChildCannotSetUp) GTEST_SKIP() << "no private mount namespace here";
  EXPECT_EQ(code, 0);
}

// The same through a file-size limit (works without mount privileges): EFBIG, "File too large".
TEST_F(Safety, FileSizeLimitFailsWithExitOne) {
  const fs::path out = dir_ / "out.exr";
  { std::ofstream(out) << "the old picture"; }
  const auto r = run_argv({"drop", "render", "-q", "--size", "128", "--samples", "1", "-o", out.string()}, [] {
    const rlimit lim{8192, 8192};
    ::setrlimit(RLIMIT_FSIZE, &lim);
  });
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("-o " + out.string() + ": writing failed: File too large; " + out.string() + " is unchanged"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(out), "the old picture");
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"out.exr"});
}

// Waits until the process has installed its signal handling (SIGINT and SIGTERM blocked in its main
// thread, taken by its sigwait thread), so that a signal tests the handler, not the default action.
void wait_until_signals_handled(pid_t pid) {
  const fs::path status = "/proc/" + std::to_string(pid) + "/status";
  while (true) {
    std::ifstream in(status);
    std::string line;
    bool ready = false, exists = false;
    while (std::getline(in, line)) {
      exists = true;
      if (line.rfind("State:", 0) == 0 && line.find('Z') != std::string::npos) return;  // it has ended
      if (line.rfind("SigBlk:", 0) == 0) {
        const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
        ready = (mask >> (SIGINT - 1) & 1) && (mask >> (SIGTERM - 1) & 1);
      }
    }
    if (ready || !exists) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

// Ctrl-C or SIGTERM during a long render: exit 130 / 143, one line saying so, the old output
// untouched, nothing left behind.
TEST_F(Safety, SignalsCancelCleanly) {
  const fs::path out = dir_ / "out.png";
  { std::ofstream(out) << "the old picture"; }
  for (const auto& [sig, code, name] : {std::tuple{SIGINT, 130, "SIGINT"}, std::tuple{SIGTERM, 143, "SIGTERM"}}) {
    const auto p = spawn({"drop", "render", "-q", "--size", "4096", "--samples", "16", "-o", out.string()});
    wait_until_signals_handled(p.pid);
    ::kill(p.pid, sig);
    const auto r = finish(p);
    EXPECT_EQ(r.code, code) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(std::string("hydrolux drop render: cancelled by ") + name), std::string::npos) << r.err;
    EXPECT_EQ(slurp(out), "the old picture");
    EXPECT_EQ(listing(dir_), std::vector<std::string>{"out.png"});
  }
}

// Ctrl-C while a Lee table is computed: exit 130, the old table untouched, and none of its three
// outputs (EXR, PNG, JSON) nor a temporary file left.
TEST_F(Safety, InterruptedLeeTableLeavesNothing) {
  const fs::path out = dir_ / "out.exr";
  { std::ofstream(out) << "the old table"; }
  const auto p = spawn({"lee", "-q", "-o", out.string()});  // the standard table: ~25 s
  wait_until_signals_handled(p.pid);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // into the computation
  ::kill(p.pid, SIGINT);
  const auto r = finish(p);
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("hydrolux lee: cancelled by SIGINT"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(out), "the old table");
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"out.exr"});
}

// Ctrl-C during hydrolux export into an existing asset folder: exit 130, the old files untouched,
// no new file, subfolder or staging folder left; and during hydrolux sky's table computation: the
// old picture kept.
TEST_F(Safety, InterruptedExportAndSkyLeaveNothing) {
  const fs::path assets = dir_ / "assets";
  fs::create_directories(assets);
  { std::ofstream(assets / "rainbow.json") << "the old axes"; }
  auto p = spawn({"export", "-q", "--dir", assets.string()});  // the standard tables: ~50 s
  wait_until_signals_handled(p.pid);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(p.pid, SIGINT);
  auto r = finish(p);
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_NE(r.err.find("hydrolux export: cancelled by SIGINT"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(assets / "rainbow.json"), "the old axes");
  EXPECT_EQ(listing(assets), std::vector<std::string>{"rainbow.json"});

  const fs::path out = dir_ / "scene.png";
  { std::ofstream(out) << "the old picture"; }
  p = spawn({"sky", "-q", "--radius-um", "1000", "-o", out.string()});  // its tables first: ~10 s
  wait_until_signals_handled(p.pid);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(p.pid, SIGINT);
  r = finish(p);
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_EQ(slurp(out), "the old picture");
  EXPECT_EQ(listing(dir_), (std::vector<std::string>{"assets", "scene.png"}));
}

// Ctrl-C during hydrolux rain over a video: exit 130, no output video and no temporary file; over a
// folder of frames: the frames written before it are whole, and no partial frame is left.
TEST_F(Safety, InterruptedRainLeavesNoPartialOutput) {
  const fs::path in = dir_ / "in.mp4";
  const std::string make = "ffmpeg -v error -y -f lavfi -i testsrc2=size=1280x720:rate=25 -frames:v 250 "
                           "-pix_fmt yuv420p -c:v libx264 -preset ultrafast " + in.string();
  ASSERT_EQ(std::system(make.c_str()), 0) << "ffmpeg (Debian's ffmpeg package; scripts/install-deps)";
  auto p = spawn({"rain", "-q", "--video", in.string(), "--rain-rate-mmh", "100", "-o", (dir_ / "out.mp4").string()});
  wait_until_signals_handled(p.pid);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // frames are being encoded
  ::kill(p.pid, SIGINT);
  auto r = finish(p);
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_NE(r.err.find("hydrolux rain: cancelled by SIGINT"), std::string::npos) << r.err;
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"in.mp4"});

  const fs::path frames = dir_ / "frames", rainy = dir_ / "rainy";
  fs::create_directories(frames);
  ASSERT_EQ(std::system(("ffmpeg -v error -y -i " + in.string() + " -frames:v 120 " + (frames / "f%03d.png").string())
                            .c_str()),
            0);
  p = spawn({"rain", "-q", "--input-dir", frames.string(), "--output-dir", rainy.string(), "--rain-rate-mmh", "100"});
  wait_until_signals_handled(p.pid);
  const auto committed = [&] {  // a frame in place (not a hidden temporary file)
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(rainy, ec))
      if (e.path().filename().string().front() != '.') return true;
    return false;
  };
  while (hydrolux::testing::still_running(p) && !committed()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ::kill(p.pid, SIGINT);
  r = finish(p);
  EXPECT_EQ(r.code, 130) << r.err;
  std::size_t written = 0;
  for (const auto& e : fs::directory_iterator(rainy)) {
    const std::string name = e.path().filename().string();
    ASSERT_NE(name.front(), '.') << "a temporary file was left: " << name;
    EXPECT_NO_THROW(hydrolux::io::read_image(e.path())) << name;  // whole
    ++written;
  }
  EXPECT_GE(written, 1u);
  EXPECT_LT(written, 120u);
}

// An interrupted gallery used to leave a half-filled folder. Now its figures are staged in a hidden
// folder (inside the gallery when it exists, beside it when it is new) and moved in at the end: a
// Ctrl-C once some figures are written removes the staging folder and leaves the previous gallery
// exactly as it was.
TEST_F(Safety, InterruptedGalleryLeavesTheOldOne) {
  const fs::path gallery = dir_ / "gallery";
  fs::create_directories(gallery);
  { std::ofstream(gallery / "index.html") << "the old gallery"; }
  const auto p = spawn({"gallery", "-q", "-o", gallery.string()});
  wait_until_signals_handled(p.pid);
  // Wait for the staging folder to hold a figure (or for the run to end, which fails below).
  bool staged = false;
  while (!staged && hydrolux::testing::still_running(p)) {
    std::error_code ec;  // the staging folder may vanish between listing and looking inside
    for (const auto& e : fs::directory_iterator(gallery, ec))
      if (e.path().filename().string().rfind(".hydrolux-staging.tmp-", 0) == 0 && !fs::is_empty(e.path(), ec))
        staged = true;
    if (!staged) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(staged) << "the gallery finished before a figure was seen staged";
  ::kill(p.pid, SIGINT);
  const auto r = finish(p);
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_NE(r.err.find("hydrolux gallery: cancelled by SIGINT; unfinished outputs removed"), std::string::npos)
      << r.err;
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"gallery"});
  EXPECT_EQ(listing(gallery), std::vector<std::string>{"index.html"});
  EXPECT_EQ(slurp(gallery / "index.html"), "the old gallery");
}

// Same inputs, same bytes: EXR (no time stamp), PNG and JSON, written more than a second apart.
TEST_F(Safety, SameInputsGiveTheSameBytes) {
  const std::vector<std::string> render = {"drop", "render", "-q", "--size", "24", "--samples", "2", "-o"};
  const auto out = [&](const std::string& name) {
    auto args = render;
    args.push_back((dir_ / name).string());
    const auto r = run_argv(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return slurp(dir_ / name);
  };
  const std::string exr = out("a.exr"), png = out("a.png");
  const auto json1 = run_argv({"rainphys", "--json"}).out;
  const auto profile1 = run_argv({"drop", "profile", "--json", "--samples", "11"}).out;
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  EXPECT_EQ(out("b.exr"), exr);
  EXPECT_EQ(out("b.png"), png);
  EXPECT_EQ(run_argv({"rainphys", "--json"}).out, json1);
  EXPECT_EQ(run_argv({"drop", "profile", "--json", "--samples", "11"}).out, profile1);
  EXPECT_FALSE(exr.empty());
}

}  // namespace
