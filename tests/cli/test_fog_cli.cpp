// hydrolux fog end to end: the image, mask and statistics of a photograph with a known depth map
// (the mask is 1 - exp(-beta d) per pixel, the image clear t + sky (1 - t)); the same bytes twice;
// the Mie route; a folder of frames; and bad input refused in one line with nothing written.
#include <gtest/gtest.h>

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
using hydrolux::testing::slurp;
using namespace hydrolux;

fs::path dir() {
  static const fs::path d = hydrolux::testing::temp_dir("hydrolux_fog_cli");
  return d;
}

const fs::path& clear_exr() {
  static const fs::path p = hydrolux::testing::builtin_frame(dir() / "clear.exr", "160x90");
  return p;
}

TEST(FogCli, TransmittanceMaskAndAirlightFromDepth) {
  const Image clear = io::read_image(clear_exr());
  Image depth(clear.width, clear.height, 1);
  for (int y = 0; y < depth.height; ++y)
    for (int x = 0; x < depth.width; ++x) depth.at(x, y, 0) = y < 20 ? INFINITY : float(10 + 2 * x + y);
  const fs::path dpath = dir() / "depth.exr", out = dir() / "fog.exr", mask = dir() / "mask.exr", stats = dir() / "s.json";
  io::write_image(dpath, depth);
  const std::string before = slurp(clear_exr());
  const auto r = run("fog -q --image " + clear_exr().string() + " --depth " + dpath.string() +
                     " --visibility-m 200 --no-glow -o " + out.string() + " --mask-out " + mask.string() +
                     " --stats-json " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_EQ(slurp(clear_exr()), before);
  const auto j = nlohmann::json::parse(slurp(stats));
  const double beta = j.at("fog").at("beta_per_m");
  EXPECT_NEAR(beta, 3.912023005428146 / 200, 1e-12);
  EXPECT_EQ(j.at("fog").at("route"), "koschmieder");
  const auto sky = j.at("frames").at(0).at("sky_rgb");
  const Image o = io::read_image(out), m = io::read_image(mask);
  ASSERT_EQ(m.channels, 1);
  // The built-in camera: 35 mm on a 36 mm sensor, the principal point at the centre.
  const double f = 35.0 / 36.0 * clear.width;
  for (int y = 0; y < clear.height; ++y)
    for (int x = 0; x < clear.width; ++x) {
      const double px = x + 0.5 - 0.5 * clear.width, py = 0.5 * clear.height - (y + 0.5);
      const double cosz = f / std::sqrt(px * px + py * py + f * f);
      const double t = std::isfinite(depth.at(x, y, 0)) ? std::exp(-beta * depth.at(x, y, 0) / cosz) : 0.0;
      ASSERT_NEAR(m.at(x, y, 0), 1 - t, 1e-6) << x << "," << y;
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(o.at(x, y, k), clear.at(x, y, k) * t + double(sky[k]) * (1 - t), 1e-5) << x << "," << y;
    }
}

TEST(FogCli, SameBytesTwiceAndMieRoute) {
  const fs::path a = dir() / "a.png", b = dir() / "b.png", stats = dir() / "mie.json";
  auto r = run("fog -q --image " + clear_exr().string() + " --visibility-m 120 -o " + a.string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("fog -q --image " + clear_exr().string() + " --visibility-m 120 -o " + b.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(a), slurp(b));
  r = run("fog -q --image " + clear_exr().string() + " --lwc-g-m3 0.37 --mode-radius-um 10 --size-alpha 3 -o " +
          (dir() / "mie.png").string() + " --stats-json " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(j.at("fog").at("route"), "mie");
  // Shettle & Fenn's heavy advection fog: ~20 cm^-3, visibility ~130 m (tests/rain/test_fog.cpp).
  EXPECT_NEAR(double(j.at("fog").at("number_per_cm3")), 20, 3);
  EXPECT_NEAR(double(j.at("fog").at("visibility_m")) / 130, 1, 0.15);
  // Without -q the summary line.
  r = run("fog --image " + clear_exr().string() + " --visibility-m 120 -o " + (dir() / "c.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("fog: 1 frame; beta"), std::string::npos) << r.err;
}

// Rain with fog in one pass (hydrolux rain --visibility-m; docs/fog.md "With rain"): the same bytes
// twice, the fog in the statistics, at 0 mm/h the fog alone on the rain's ground plane (its backdrop
// given to both), and a fog setting without a fog refused in one line.
TEST(FogCli, RainWithFogOnePass) {
  const fs::path a = dir() / "rf_a.exr", b = dir() / "rf_b.exr", stats = dir() / "rf.json";
  const std::string in = " --image " + clear_exr().string();
  auto r = run("rain -q" + in + " --rain-rate-mmh 25 --visibility-m 200 -o " + a.string() + " --stats-json " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("rain -q" + in + " --rain-rate-mmh 25 --visibility-m 200 -o " + b.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(a), slurp(b));
  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_NEAR(double(j.at("frames").at(0).at("fog").at("visibility_m")), 200, 1e-9);
  const fs::path dry = dir() / "rf_dry.exr", fog = dir() / "rf_fog.exr";
  r = run("rain -q" + in + " --rain-rate-mmh 0 --backdrop-m 300 --visibility-m 200 -o " + dry.string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("fog -q" + in + " --backdrop-m 300 --visibility-m 200 -o " + fog.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Image x = io::read_image(dry), y = io::read_image(fog);
  ASSERT_EQ(x.pixels.size(), y.pixels.size());
  double worst = 0;
  for (std::size_t i = 0; i < x.pixels.size(); ++i) worst = std::max(worst, double(std::abs(x.pixels[i] - y.pixels[i])));
  EXPECT_LT(worst, 1e-5);
  r = run("rain -q" + in + " --rain-rate-mmh 25 --size-alpha 6 -o " + (dir() / "rf_c.png").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--size-alpha: sets the fog"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir() / "rf_c.png"));
}

// "f<k>.exr" (appended: GCC 12's -Wrestrict misfires on a literal + std::to_string + a literal at -O3).
std::string frame_name(int k) {
  std::string name = "f";
  name += std::to_string(k);
  name += ".exr";
  return name;
}

TEST(FogCli, FolderOfFrames) {
  const fs::path in = dir() / "frames", out = dir() / "foggy", masks = dir() / "masks";
  fs::create_directories(in);
  for (int k = 0; k < 3; ++k) fs::copy_file(clear_exr(), in / frame_name(k), fs::copy_options::overwrite_existing);
  const auto r = run("fog -q --input-dir " + in.string() + " --output-dir " + out.string() + " --mask-dir " +
                     masks.string() + " --visibility-m 300");
  ASSERT_EQ(r.code, 0) << r.err;
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(fs::exists(out / frame_name(k)));
    EXPECT_TRUE(fs::exists(masks / frame_name(k)));
  }
  // One fog over identical frames: identical outputs.
  EXPECT_EQ(slurp(out / "f0.exr"), slurp(out / "f2.exr"));
}

TEST(FogCli, BadInputOneLineNothingWritten) {
  const std::string img = " --image " + clear_exr().string();
  const std::string o = " -o " + (dir() / "bad.png").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"fog" + img + o, "--visibility-m"},
      {"fog" + img + " --visibility-m 0.5" + o, "--visibility-m"},
      {"fog" + img + " --visibility-m abc" + o, "--visibility-m"},
      {"fog" + img + " --visibility-m 100 --lwc-g-m3 0.1" + o, "--lwc-g-m3"},
      {"fog" + img + " --lwc-g-m3 9" + o, "--lwc-g-m3"},
      {"fog" + img + " --lwc-g-m3 0.1 --mode-radius-um 100" + o, "--mode-radius-um"},
      {"fog" + img + " --visibility-m 100 --size-alpha 0" + o, "--size-alpha"},
      {"fog" + img + " --visibility-m 100 -o " + (dir() / "bad.txt").string(), "-o"},
      {"fog" + img + " --visibility-m 100" + o + " --depth " + (dir() / "missing.exr").string(), "--depth"},
      {"fog --image " + (dir() / "missing.png").string() + " --visibility-m 100" + o, "--image"},
      {"fog" + img + " --visibility-m 100 --output-dir " + (dir() / "x").string() + o, "--output-dir"},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists(dir() / "bad.png"));
  EXPECT_FALSE(fs::exists(dir() / "x"));
}

}  // namespace
