// hydrolux rain against the holes a hostile probe found (issue 23): an output on any file the run
// reads, in a folder or not (the data loss); non-finite and negative input values; flags given where
// they would be ignored; a seed above 2^53; a frame size that cannot fit in memory; a bad frame in
// the middle of a folder; messages naming the flag the user gave.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/io/image_io.hpp"
#include "support/asan.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::lines;
using hydrolux::testing::run;
using hydrolux::testing::slurp;
using namespace hydrolux;

fs::path dir() {
  static const fs::path d = hydrolux::testing::temp_dir("hydrolux_rain_hostile");
  return d;
}

// A folder of `n` clear 160x90 frames (the built-in street), made once per name.
fs::path frames_dir(const std::string& name, int n) {
  const fs::path d = dir() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  const auto r = run("rain -q --image builtin --size 160x90 --rain-rate-mmh 0 -o " + (d / "f_000.png").string());
  EXPECT_EQ(r.code, 0) << r.err;
  for (int k = 1; k < n; ++k)
    fs::copy_file(d / "f_000.png", d / ("f_00" + std::to_string(k) + ".png"), fs::copy_options::overwrite_existing);
  return d;
}

std::map<fs::path, std::string> snapshot(const fs::path& d) {
  std::map<fs::path, std::string> m;
  for (const auto& e : fs::directory_iterator(d))
    if (fs::is_regular_file(e.symlink_status())) m[e.path().filename()] = slurp(e.path());
  return m;
}

// The data loss: --stats-json on a frame replaced the frame with JSON and exited 0. Every file the run
// reads (frames, depth maps) and every file it writes (frames, masks, the statistics) is now declared
// before any work, so an output on any of them, whichever folder it is in, is refused.
TEST(RainHostile, NoOutputLandsOnAnyFileTheRunReadsOrWrites) {
  const fs::path frames = frames_dir("frames", 2);
  const fs::path depth = dir() / "depth";
  fs::create_directories(depth);
  ASSERT_EQ(run("rain -q --image builtin --size 160x90 --rain-rate-mmh 0 -o " + (depth / "f_000.png").string()).code, 0);
  fs::copy_file(depth / "f_000.png", depth / "f_001.png", fs::copy_options::overwrite_existing);
  const fs::path out = dir() / "out", masks = dir() / "masks";
  fs::create_directories(out);
  fs::create_directories(masks);
  // A link in the output folder to an input frame: writing through it would replace the frame.
  fs::create_symlink(fs::absolute(frames / "f_001.png"), out / "f_001.png");
  const auto before = snapshot(frames), before_depth = snapshot(depth);
  const std::string base = "rain -q --input-dir " + frames.string() + " --output-dir ";
  const std::string fresh = (dir() / "fresh").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base + fresh + " --stats-json " + (frames / "f_000.png").string(), "--stats-json"},
      {base + fresh + " --depth-dir " + depth.string() + " --stats-json " + (depth / "f_001.png").string(),
       "--stats-json"},
      {base + fresh + " --stats-json " + fresh + "/f_001.png", "--stats-json"},
      {base + fresh + " --mask-dir " + masks.string() + " --stats-json " + (masks / "f_000.png").string(),
       "--stats-json"},
      {base + out.string(), "--output-dir"},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_EQ(snapshot(frames), before);
  EXPECT_EQ(snapshot(depth), before_depth);
  EXPECT_FALSE(fs::exists(fresh));
  EXPECT_TRUE(fs::is_symlink(out / "f_001.png"));
}

// A FIFO or a dangling link named like a frame is listed, not skipped without a word.
TEST(RainHostile, EntriesThatAreNotFilesAreListed) {
  const fs::path frames = frames_dir("special", 1);
  ASSERT_EQ(::mkfifo((frames / "pipe.png").c_str(), 0600), 0);
  fs::create_symlink(frames / "missing.png", frames / "dangling.png");
  const auto r = run("rain --input-dir " + frames.string() + " --output-dir " + (dir() / "special_out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("skipped 2 entries that are not regular files: dangling.png (dangling link), pipe.png (FIFO)"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(dir() / "special_out" / "f_000.png"));
}

// An EXR frame of width x height with one value replaced.
fs::path exr_with(const std::string& name, float value, int x, int y, int k) {
  const Image clear = io::read_image(frames_dir("src_" + name, 1) / "f_000.png");
  Image img = clear;
  img.at(x, y, k) = value;
  const fs::path p = dir() / (name + ".exr");
  io::write_image(p, img);
  return p;
}

TEST(RainHostile, NonFiniteInputIsRefusedNamingThePixel) {
  for (const float v : {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    const fs::path in = exr_with(std::isnan(v) ? "nan" : "inf", v, 17, 5, 1);
    const fs::path o = dir() / "nonfinite_out.exr";
    const auto r = run("rain -q --image " + in.string() + " --rain-rate-mmh 25 -o " + o.string());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("--image " + in.string() + ": pixel (17, 5) channel 1 is"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(o));
  }
}

TEST(RainHostile, NegativeInputIsReadAsZeroAndSaid) {
  const fs::path neg = exr_with("negative", -0.25f, 3, 4, 0);
  const fs::path zero = exr_with("zero", 0.0f, 3, 4, 0);
  const fs::path a = dir() / "neg_out.exr", b = dir() / "zero_out.exr", sa = dir() / "neg.json";
  const auto r = run("rain --image " + neg.string() + " --rain-rate-mmh 25 -o " + a.string() + " --stats-json " + sa.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: --image " + neg.string() + ": 1 negative value read as 0"), std::string::npos) << r.err;
  ASSERT_EQ(run("rain -q --image " + zero.string() + " --rain-rate-mmh 25 -o " + b.string()).code, 0);
  EXPECT_EQ(slurp(a), slurp(b));  // exactly as if the value were 0
  const Image out = io::read_image(a);
  for (const float v : out.pixels) ASSERT_TRUE(std::isfinite(v) && v >= 0);
  EXPECT_EQ(nlohmann::json::parse(slurp(sa)).at("frames").at(0).at("negative_values_clamped"), 1);
}

// A bad frame in the middle of a folder: named and left out, the others written, exit 1 (it used to
// be exit 2, "nothing written", after the first frames were written).
TEST(RainHostile, BadFrameMidwayIsNamedAndTheOthersWritten) {
  const fs::path frames = frames_dir("midway", 3);
  const std::string png = slurp(frames / "f_001.png");
  {
    std::ofstream(frames / "f_001.png", std::ios::binary | std::ios::trunc) << png.substr(0, png.size() / 2);
  }
  const fs::path out = dir() / "midway_out", stats = dir() / "midway.json";
  const auto r = run("rain -q --input-dir " + frames.string() + " --output-dir " + out.string() + " --stats-json " +
                     stats.string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("f_001.png"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 of 3 frames left out (f_001.png)"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "f_000.png"));
  EXPECT_FALSE(fs::exists(out / "f_001.png"));
  EXPECT_TRUE(fs::exists(out / "f_002.png"));
  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(j.at("frames").size(), 2u);
  EXPECT_EQ(j.at("left_out").at(0), "f_001.png");
}

// Flags that would be accepted and ignored are refused; a seed above 2^53 is refused (it used to
// collapse onto 2^53); a size that cannot fit in memory is refused before the work; messages name
// the flag the user gave.
TEST(RainHostile, IgnoredFlagsWrongFlagsAndUnboundedWorkAreRefused) {
  const fs::path frames = frames_dir("flags", 1);
  const fs::path exr_depth = dir() / "depth.exr", tiny_depth = dir() / "tiny.exr";
  io::write_image(exr_depth, Image(160, 90, 1));
  io::write_image(tiny_depth, Image(1, 1, 1));
  const std::string o = (dir() / "flags_out.png").string(), img = "rain -q --image builtin --size 160x90 ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {img + "--crf 20 -o " + o, "--crf"},
      {img + "--depth-scale-m 0.01 -o " + o, "--depth-scale-m"},
      {img + "--depth " + exr_depth.string() + " --depth-scale-m 0.01 -o " + o, "--depth-scale-m"},
      {img + "--depth " + tiny_depth.string() + " -o " + o, "--depth " + tiny_depth.string() + ": 1x1 is too coarse"},
      {"rain -q --input-dir " + frames.string() + " --output-dir " + (dir() / "x").string() + " --crf 3", "--crf"},
      {img + "--seed 9007199254740993 -o " + o, "--seed: 9007199254740993 is outside the valid range [0, 9007199254740992]"},
      {img + "--fov-deg 1 -o " + o,
       "--fov-deg 1 is outside the valid range [1.0313, 170] deg of a 36 mm wide sensor (focal lengths 1-2000 mm)"},
      {img + "--near-m 5 --far-m 2 -o " + o, "--far-m 2 is outside the valid range [5.005, 10000] m (beyond --near-m)"},
      {img + "--min-radius-mm 1 --max-radius-mm 0.5 -o " + o, "(beyond --min-radius-mm)"},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists(o));

  // 4000x4000 needs about 1.3 GB: under a 600 MB address-space limit it is refused in a moment, naming
  // --size and a size that fits, where it used to run until the allocator failed. Without
  // AddressSanitizer, whose shadow memory needs far more address space.
#if !HYDROLUX_TEST_ASAN
  const auto r = hydrolux::testing::run_argv({"rain", "-q", "--image", "builtin", "--size", "4000x4000", "-o", o}, [] {
    const rlimit lim{std::uint64_t(600) << 20, std::uint64_t(600) << 20};
    ::setrlimit(RLIMIT_AS, &lim);
  });
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("--size 4000x4000: rain over 4000x4000 needs about"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("would fit"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(o));
#endif
}

// A 0.5 frames/s video (a time lapse) used to be refused as "--fps 0.5", a flag not given and not
// allowed with --video, so it could not be processed at all: its rate is now in the camera's range.
TEST(RainHostile, TimeLapseVideoIsProcessed) {
  const fs::path in = dir() / "slow.mp4", out = dir() / "slow_out.mp4";
  ASSERT_EQ(std::system(("ffmpeg -loglevel error -y -f lavfi -i testsrc=size=160x90:rate=0.5 -t 6 -c:v libx264 "
                         "-pix_fmt yuv420p " + in.string()).c_str()),
            0);
  const auto r = run("rain -q --video " + in.string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(fs::file_size(out), 0u);
}

}  // namespace

namespace {

// Issue 37's silent surprises in a folder run: a --depth-dir holding two maps for one frame picked one
// silently; a float frame (.pfm, .hdr) came out as an 8-bit PNG; a one-channel image was blamed on its
// size.
TEST(RainHostile, AmbiguousDepthMapsFloatFramesAndGreyImagesAreSaidPlainly) {
  const fs::path frames = frames_dir("surprises", 1);
  const fs::path depth = dir() / "surprises_depth";
  fs::create_directories(depth);
  io::write_image(depth / "f_000.exr", Image(160, 90, 1));
  fs::copy_file(frames / "f_000.png", depth / "f_000.png", fs::copy_options::overwrite_existing);
  const fs::path out = dir() / "surprises_out";
  auto r = run("rain -q --input-dir " + frames.string() + " --depth-dir " + depth.string() + " --output-dir " +
               out.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("both f_000.exr and f_000.png are depth maps for f_000.png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));

  // A PFM frame (32-bit float light, here above 1) stays float: the output is f_001.exr.
  {
    const int w = 160, h = 90;
    std::ofstream pfm(frames / "f_001.pfm", std::ios::binary);
    pfm << "PF\n" << w << " " << h << "\n-1.0\n";
    std::vector<float> px(std::size_t(w) * h * 3, 2.5f);
    pfm.write(reinterpret_cast<const char*>(px.data()), std::streamsize(px.size() * sizeof(float)));
  }
  r = run("rain -q --rain-rate-mmh 0 --input-dir " + frames.string() + " --output-dir " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "f_000.png"));
  ASSERT_TRUE(fs::exists(out / "f_001.exr"));
  EXPECT_FALSE(fs::exists(out / "f_001.png"));
  const Image back = io::read_image(out / "f_001.exr");
  EXPECT_GT(back.at(80, 45, 0), 2.0f);  // light above 1 kept, not clipped to an 8-bit code

  // One channel: the message says what is missing (colour), not that the size is wrong.
  const fs::path grey = dir() / "grey.exr";
  io::write_image(grey, Image(160, 90, 1));
  r = run("rain -q --image " + grey.string() + " -o " + (dir() / "grey_out.png").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("1 channel; rain needs colour"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("size"), std::string::npos) << r.err;
}

}  // namespace
