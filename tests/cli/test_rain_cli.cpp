// hydrolux rain end to end: a photograph's outputs (image, mask, layer, stats) and the exact pairing
// rainy = clear (1 - alpha) + layer; the same seed giving the same bytes; inputs never touched; a
// folder of frames in name order with one rain field; a depth map hiding the rain behind nearer
// geometry; a video keeping its frame count and rate; and bad input refused in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hydrolux/io/image_io.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::run;
using hydrolux::testing::ffprobe_csv;
using hydrolux::testing::slurp;
using namespace hydrolux;

fs::path dir() {
  static const fs::path d = hydrolux::testing::temp_dir("hydrolux_rain_cli");
  return d;
}

// The built-in street, clear, as a linear EXR and an 8-bit PNG (made once).
const fs::path& clear_exr() {
  static const fs::path p = hydrolux::testing::builtin_frame(dir() / "clear.exr", "320x180");
  return p;
}
const fs::path& clear_png() {
  static const fs::path p = hydrolux::testing::builtin_frame(dir() / "clear.png", "320x180");
  return p;
}

TEST(RainCli, ImageMaskLayerAndStatsPairExactly) {
  const fs::path out = dir() / "rainy.exr", mask = dir() / "mask.exr", layer = dir() / "layer.exr",
                 mask_png = dir() / "mask.png", stats = dir() / "stats.json";
  const std::string before = slurp(clear_exr());
  auto r = run("rain -q --image " + clear_exr().string() + " --rain-rate-mmh 50 --wind-mps 3 --seed 7 -o " + out.string() +
               " --mask-out " + mask.string() + " --layer-out " + layer.string() + " --stats-json " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;  // -q
  EXPECT_EQ(slurp(clear_exr()), before);  // the input is never modified
  const Image c = io::read_image(clear_exr()), o = io::read_image(out), a = io::read_image(mask),
              l = io::read_image(layer);
  ASSERT_EQ(a.channels, 1);
  ASSERT_EQ(l.channels, 4);
  // rainy = clear (1 - alpha) + layer, per pixel and channel (float rounding only).
  double alpha_sum = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const float al = a.at(x, y, 0);
      alpha_sum += al;
      ASSERT_FLOAT_EQ(l.at(x, y, 3), al);
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(o.at(x, y, k), c.at(x, y, k) * (1 - al) + l.at(x, y, k), 1e-5) << x << "," << y;
    }
  EXPECT_GT(alpha_sum, 0);

  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(j.at("seed"), 7);
  EXPECT_EQ(j.at("rain").at("rain_rate_mmh"), 50);
  EXPECT_EQ(j.at("camera").at("width"), 320);
  EXPECT_GT(j.at("field").at("drops"), 1000);
  const auto& f = j.at("frames").at(0);
  EXPECT_GT(f.at("drops_in_view"), 100);
  EXPECT_LE(f.at("drops_visible"), f.at("drops_in_view"));
  EXPECT_GT(f.at("streak_length_px").at("p95"), f.at("streak_length_px").at("p50"));

  // A pixel pitch gives the same camera as the sensor width it implies (36 mm over 320 px: 112.5 um).
  r = run("rain -q --image " + clear_exr().string() + " --rain-rate-mmh 50 --wind-mps 3 --seed 7 --pixel-pitch-um 112.5 -o " +
          (dir() / "pitch.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(dir() / "pitch.exr"), slurp(out));

  // The PNG mask holds alpha as 16-bit linear codes, alpha x 65535, and says so (gAMA 1.0, no sRGB
  // chunk): hydrolux's reader gives alpha back within half a code (issue 37; it read 0.17 as 0.02).
  r = run("rain -q --image " + clear_exr().string() + " --rain-rate-mmh 50 --wind-mps 3 --seed 7 -o " +
          (dir() / "rainy.png").string() + " --mask-out " + mask_png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string mask_bytes = slurp(mask_png);
  EXPECT_EQ(mask_bytes.find("sRGB"), std::string::npos);
  EXPECT_NE(mask_bytes.find(std::string("gAMA\x00\x01\x86\xa0", 8)), std::string::npos);  // 100000
  const auto decoded = io::decode_image(mask_bytes, "mask");
  EXPECT_TRUE(decoded.linear);
  double worst = 0, most = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    worst = std::max(worst, std::abs(double(decoded.image.pixels[i]) - a.pixels[i]));
    most = std::max(most, double(a.pixels[i]));
  }
  EXPECT_LE(worst, 0.5 / 65535 + 1e-7);
  EXPECT_GT(most, 0.1);  // coverage where the curve and the line differ
}

TEST(RainCli, SameSeedSameBytes) {
  const auto make = [](const std::string& name, int seed) {
    const fs::path f = dir() / name;
    const auto r = run("rain -q --image " + clear_png().string() + " --rain-rate-mmh 25 --seed " + std::to_string(seed) +
                       " -o " + f.string());
    EXPECT_EQ(r.code, 0) << r.err;
    return slurp(f);
  };
  const std::string a = make("s1a.png", 1), b = make("s1b.png", 1), c = make("s2.png", 2);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_NE(a, slurp(clear_png()));
}

// Issue 38: the rain rate is --rain-rate-mmh in every job. The old --rate-mmh is taken for one release:
// the same bytes, with one line on stderr naming the new flag; giving both is a usage error naming both.
TEST(RainCli, DeprecatedRateMmhWarnsOnceAndGivesTheSameBytes) {
  const std::string in = " -q --image " + clear_png().string() + " --seed 3 --stats-json ";
  const fs::path now = dir() / "rate_now.png", old = dir() / "rate_old.png";
  const auto a = run("rain" + in + (dir() / "rate_now.json").string() + " --rain-rate-mmh 5 -o " + now.string());
  ASSERT_EQ(a.code, 0) << a.err;
  const auto b = run("rain" + in + (dir() / "rate_old.json").string() + " --rate-mmh 5 -o " + old.string());
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(slurp(now), slurp(old));
  EXPECT_EQ(a.out, b.out);
  // The only difference on stderr (-q: nothing else) is the one warning line.
  EXPECT_EQ(a.err, "");
  EXPECT_EQ(b.err,
            "hydrolux rain: warning: --rate-mmh is deprecated and will be removed in the next release: give "
            "--rain-rate-mmh (the same value in mm/h)\n");
  // The run's record names the quantity by its one name.
  const auto j = nlohmann::json::parse(slurp(dir() / "rate_old.json"));
  EXPECT_EQ(j.at("rain").at("rain_rate_mmh"), 5);
  EXPECT_FALSE(j.at("rain").contains("rate_mmh"));

  const auto both = run("rain -q --image builtin --rate-mmh 5 --rain-rate-mmh 5 -o " + (dir() / "both.png").string());
  EXPECT_EQ(both.code, 2) << both.err;
  EXPECT_TRUE(both.out.empty());
  EXPECT_NE(both.err.find("--rate-mmh: give --rain-rate-mmh or --rate-mmh (its deprecated name), not both"),
            std::string::npos)
      << both.err;
  EXPECT_EQ(std::count(both.err.begin(), both.err.end(), '\n'), 1) << both.err;
  EXPECT_FALSE(fs::exists(dir() / "both.png"));
  // The old flag has the new one's range, and --help shows only the new one.
  const auto high = run("rain -q --image builtin --rate-mmh 600 -o " + (dir() / "high.png").string());
  EXPECT_EQ(high.code, 2);
  EXPECT_NE(high.err.find("[0, 500]"), std::string::npos) << high.err;
  const auto help = run("rain --help");
  EXPECT_NE(help.out.find("--rain-rate-mmh"), std::string::npos);
  EXPECT_EQ(help.out.find("--rate-mmh"), std::string::npos);
}

TEST(RainCli, FolderOfFramesIsOneRain) {
  const fs::path in = dir() / "frames", out = dir() / "rainy", masks = dir() / "masks";
  fs::create_directories(in);
  for (const char* n : {"b.png", "a.png", "c.png"}) fs::copy_file(clear_png(), in / n, fs::copy_options::overwrite_existing);
  fs::copy_file(clear_exr(), in / "d.exr", fs::copy_options::overwrite_existing);
  const std::string stats = (dir() / "frames.json").string();
  auto r = run("rain -q --input-dir " + in.string() + " --output-dir " + out.string() + " --mask-dir " +
               masks.string() + " --rain-rate-mmh 25 --stats-json " + stats);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* n : {"a.png", "b.png", "c.png", "d.exr"}) {
    EXPECT_TRUE(fs::is_regular_file(out / n)) << n;
    EXPECT_TRUE(fs::is_regular_file(masks / n)) << n;
  }
  // Name order: a, b, c, d are frames 0..3 of one field; frame 0 equals a single image at index 0.
  const auto j = nlohmann::json::parse(slurp(stats));
  ASSERT_EQ(j.at("frames").size(), 4u);
  EXPECT_EQ(j.at("frames").at(0).at("input"), "a.png");
  EXPECT_EQ(j.at("frames").at(3).at("frame_index"), 3);
  r = run("rain -q --image " + (in / "a.png").string() + " --rain-rate-mmh 25 -o " + (dir() / "single.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(out / "a.png"), slurp(dir() / "single.png"));
  // --frame-index 1 is the folder's second frame (the same input picture).
  r = run("rain -q --image " + (in / "b.png").string() + " --rain-rate-mmh 25 --frame-index 1 -o " +
          (dir() / "second.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(out / "b.png"), slurp(dir() / "second.png"));
  EXPECT_NE(slurp(out / "a.png"), slurp(out / "b.png"));  // the rain moved on
  // The inputs are untouched and the output folder holds nothing else (no temporary files).
  EXPECT_EQ(slurp(in / "a.png"), slurp(clear_png()));
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(out)) ++n;
  EXPECT_EQ(n, 4u);
}

TEST(RainCli, DepthMapHidesRainBehindNearerGeometry) {
  // A 16-bit PNG depth map: codes x 1 mm. Left half a wall at 0.3 m (nearer than every drop, which
  // start at --near-m 0.5), right half code 0 (no geometry): the wall's pixels stay exactly clear.
  const fs::path depth = dir() / "depth.png", out = dir() / "walled.exr", mask = dir() / "walled_mask.exr";
  Image d(320, 180, 1);
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) {
      const double code = x < 160 ? 300 : 0;
      // The encoder applies the sRGB curve to grey: hand it the code's linear value.
      const double v = code / 65535;
      d.at(x, y, 0) = float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    }
  io::write_image(depth, d, io::PngOptions{16});
  auto r = run("rain -q --image " + clear_exr().string() + " --depth " + depth.string() +
               " --depth-scale-m 0.001 --rain-rate-mmh 100 -o " + out.string() + " --mask-out " + mask.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Image a = io::read_image(mask), o = io::read_image(out), c = io::read_image(clear_exr());
  double left = 0, right = 0;
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) (x < 160 ? left : right) += a.at(x, y, 0);
  // Left: no streak, and the unresolved rain over 0.3 m before the wall is none (it starts at near_m).
  EXPECT_EQ(left, 0);
  EXPECT_GT(right, 0);
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 160; ++x) ASSERT_EQ(o.at(x, y, 0), c.at(x, y, 0));
}

TEST(RainCli, FolderWithDepthMapsPerFrame) {
  // Two frames; frame b's depth map walls off the left half nearer than every drop, frame a's is
  // open (code 0: no geometry). Only b's left half stays exactly clear.
  const fs::path in = dir() / "dframes", depths = dir() / "depths", out = dir() / "drainy";
  fs::create_directories(in);
  fs::create_directories(depths);
  for (const char* n : {"a.exr", "b.exr"}) fs::copy_file(clear_exr(), in / n, fs::copy_options::overwrite_existing);
  Image open(320, 180, 1), wall(320, 180, 1);
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) wall.at(x, y, 0) = x < 160 ? 0.3f : 0.f;  // metres (EXR); 0: none
  io::write_image(depths / "a.exr", open);
  io::write_image(depths / "b.exr", wall);
  auto r = run("rain -q --input-dir " + in.string() + " --depth-dir " + depths.string() + " --output-dir " +
               out.string() + " --rain-rate-mmh 100");
  ASSERT_EQ(r.code, 0) << r.err;
  const Image c = io::read_image(clear_exr()), a = io::read_image(out / "a.exr"), b = io::read_image(out / "b.exr");
  int a_changed = 0;
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 160; ++x) {
      ASSERT_EQ(b.at(x, y, 1), c.at(x, y, 1)) << x << "," << y;
      a_changed += a.at(x, y, 1) != c.at(x, y, 1);
    }
  EXPECT_GT(a_changed, 1000);
  // A frame without its depth map is refused before any work, naming it.
  fs::copy_file(clear_exr(), in / "c.exr", fs::copy_options::overwrite_existing);
  r = run("rain -q --input-dir " + in.string() + " --depth-dir " + depths.string() + " --output-dir " +
          (dir() / "drainy2").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--depth-dir"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("c.exr"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir() / "drainy2"));
}

TEST(RainCli, VideoKeepsFrameCountAndRate) {
  const fs::path in = dir() / "in.mp4", out = dir() / "out.mp4", stats = dir() / "video.json";
  const std::string make = "ffmpeg -v error -y -f lavfi -i testsrc2=size=160x96:rate=30000/1001 -frames:v 24 "
                           "-pix_fmt yuv420p -c:v libx264 " + in.string();
  ASSERT_EQ(std::system(make.c_str()), 0) << "ffmpeg (Debian's ffmpeg package; scripts/install-deps)";
  const std::string before = slurp(in);
  const auto r = run("rain -q --video " + in.string() + " --rain-rate-mmh 50 -o " + out.string() + " --stats-json " +
                     stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(in), before);
  EXPECT_EQ(ffprobe_csv(out), "160,96,30000/1001,24\n");
  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(j.at("frames").size(), 24u);
  EXPECT_NEAR(double(j.at("camera").at("fps")), 30000.0 / 1001, 1e-9);
}

TEST(RainCli, BadInputIsRefusedInOneLine) {
  const std::string img = clear_png().string(), o = (dir() / "bad.png").string();
  const fs::path frames = dir() / "same";
  fs::create_directories(frames);
  fs::copy_file(clear_png(), frames / "a.png", fs::copy_options::overwrite_existing);
  const fs::path clash = dir() / "clash";  // a.png and a.jpg would both become a.png
  fs::create_directories(clash);
  fs::copy_file(clear_png(), clash / "a.png", fs::copy_options::overwrite_existing);
  fs::copy_file(clear_png(), clash / "a.jpg", fs::copy_options::overwrite_existing);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"rain -o " + o, "--image"},
      {"rain --image " + img + " --input-dir " + dir().string() + " -o " + o, "--input-dir"},
      {"rain --image " + img + " --rain-rate-mmh 900 -o " + o, "--rain-rate-mmh"},
      {"rain --image " + img + " --exposure-s 0.5 -o " + o, "--exposure-s"},
      {"rain --image " + img + " --exposure-s 0.02 --fps 60 -o " + o, "--exposure-s"},
      {"rain --image " + img + " --near-m 5 --far-m 2 -o " + o, "--far-m"},
      {"rain --image " + img + " --f-number 2 --focus-m 0.02 -o " + o, "--focus-m"},
      {"rain --image " + img + " --layer-out " + (dir() / "l.png").string() + " -o " + o, "--layer-out"},
      {"rain --image " + img + " -o " + img, "-o"},
      {"rain --image " + img + " --size 64x64 -o " + o, "--size"},
      {"rain --input-dir " + dir().string() + " -o " + o, "-o"},
      {"rain --input-dir " + frames.string() + " --output-dir " + frames.string() + "/.", "--output-dir"},
      {"rain --video " + img + " -o " + (dir() / "v.mp4").string(), "--video"},
      {"rain --input-dir " + clash.string() + " --output-dir " + (dir() / "clash_out").string(), "a.png"},
      {"rain --video " + img + " -o " + (dir() / "v.avi").string(), "-o"},
      {"rain --image builtin --size 1920x1080 --min-alpha 0.00001 --rain-rate-mmh 500 --far-m 10000 -o " + o, "--min-alpha"},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists(dir() / "bad.png"));
  EXPECT_FALSE(fs::exists(dir() / "clash_out"));
}

}  // namespace
