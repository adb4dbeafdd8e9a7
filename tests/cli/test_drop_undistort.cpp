// `hydrolux drop undistort` as a user runs it: a perspective view of the requested size from a
// drop image, and one-line usage errors (exit code 2, the flag named) that leave no output behind.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "hydrolux/core/image.hpp"
#include "hydrolux/io/image_io.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::lines;
using hydrolux::testing::run;

fs::path temp_dir() { return hydrolux::testing::temp_dir("hydrolux_undistort"); }

// A 64 x 48 PNG with a uniform grey disk (linear 0.25) of radius 20 px centred at (30, 24) on black.
fs::path write_drop_png(const fs::path& dir) {
  hydrolux::Image img(64, 48, 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (std::hypot(x + 0.5 - 30, y + 0.5 - 24) < 20)
        for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.25f;
  const auto path = dir / "drop.png";
  hydrolux::io::write_image(path, img);
  return path;
}

TEST(DropUndistortCli, WritesTheRequestedSize) {
  const auto dir = temp_dir();
  const std::string in = " --image " + write_drop_png(dir).string() + " --drop-center 30,24 --drop-radius-px 20";

  // EXR, --size: linear RGBA; at the view's centre the drop's centre, divided by the transmission
  // (1 - k)^2 at normal incidence, k = (0.333 / 2.333)^2.
  const auto exr = dir / "view.exr";
  auto r = run("drop undistort" + in + " --size 40x30 --fov-deg 90 -q -o " + exr.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  auto img = hydrolux::io::read_image(exr);
  EXPECT_EQ(img.width, 40);
  EXPECT_EQ(img.height, 30);
  ASSERT_EQ(img.channels, 4);
  const double T0 = std::pow(1 - std::pow(0.333 / 2.333, 2), 2);
  const double grey = hydrolux::io::read_image(dir / "drop.png").at(30, 24, 0);  // 0.25 after 8 bits
  EXPECT_NEAR(img.at(20, 15, 0), grey / T0, 1e-6);
  EXPECT_EQ(img.at(20, 15, 3), 1.f);

  // PNG, --width alone (square), no transmission correction, a 175 degree field: its left and
  // right edges lie beyond the drop's 165.6 degree field of view, alpha 0 there.
  const auto png = dir / "view.png";
  r = run("drop undistort" + in + " --width 21 --fov-deg 175 --no-transmission-correction -o " + png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;  // the summary
  img = hydrolux::io::read_image(png);
  EXPECT_EQ(img.width, 21);
  EXPECT_EQ(img.height, 21);
  ASSERT_EQ(img.channels, 4);
  EXPECT_NEAR(img.at(10, 10, 1), grey, 0.005);  // within one 8-bit sRGB code
  EXPECT_EQ(img.at(10, 10, 3), 1.f);
  EXPECT_EQ(img.at(0, 10, 3), 0.f);
  EXPECT_EQ(img.at(20, 10, 3), 0.f);

  // Default size 512 x 512.
  r = run("drop undistort" + in + " --yaw-deg 10 --pitch-deg -5 -q -o " + png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  img = hydrolux::io::read_image(png);
  EXPECT_EQ(img.width, 512);
  EXPECT_EQ(img.height, 512);
  fs::remove_all(dir);
}

TEST(DropUndistortCli, UsageErrors) {
  const auto dir = temp_dir();
  const auto drop = write_drop_png(dir);
  const auto out = dir / "x.png";
  const std::string o = " -o " + out.string();
  const std::string image = " --image " + drop.string();
  const std::string ok = image + " --drop-center 30,24 --drop-radius-px 20";
  const std::pair<std::string, const char*> cases[] = {
      {"drop undistort --drop-center 30,24 --drop-radius-px 20" + o, "--image"},
      {"drop undistort" + image + " --drop-radius-px 20" + o, "--drop-center"},
      {"drop undistort" + image + " --drop-center '30;24' --drop-radius-px 20" + o, "--drop-center"},
      {"drop undistort" + image + " --drop-center 30 --drop-radius-px 20" + o, "--drop-center"},
      {"drop undistort" + image + " --drop-center 30,abc --drop-radius-px 20" + o, "--drop-center"},
      {"drop undistort" + image + " --drop-center 30,24 --drop-radius-px -20" + o, "--drop-radius-px"},
      {"drop undistort" + image + " --drop-center 30,24 --drop-radius-px 0" + o, "--drop-radius-px"},
      {"drop undistort" + ok + " --fov-deg 0" + o, "--fov-deg"},
      {"drop undistort" + ok + " --fov-deg 200" + o, "--fov-deg"},
      {"drop undistort" + ok + " --pitch-deg 100" + o, "--pitch-deg"},
      {"drop undistort" + ok + " --mu 0.9" + o, "--mu"},
      {"drop undistort" + ok + " --size 10x" + o, "--size"},
      {"drop undistort" + ok + " --size 10x10 --width 5" + o, "--size"},
      {"drop undistort" + ok + " --width 0" + o, "--width"},
      {"drop undistort" + ok, "--output"},
      {"drop undistort" + ok + " -o " + (dir / "x.jpg").string(), "-o"},
      {"drop undistort" + ok + " -o /nonexistent-dir/x.png", "-o"},
      {"drop undistort --image " + (dir / "nope.png").string() + " --drop-center 30,24 --drop-radius-px 20" + o,
       "--image"},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists(out));  // nothing written on any error
  EXPECT_FALSE(fs::exists(dir / "x.jpg"));
  fs::remove_all(dir);
}

}  // namespace
