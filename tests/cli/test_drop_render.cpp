// `hydrolux drop render` as a user runs it: images of the requested size and format from the
// builtin environment or a file, and one-line usage errors that leave no output file behind.
#include <gtest/gtest.h>

#include <filesystem>

#include "hydrolux/io/image_io.hpp"
#include "hydrolux/scene/environment.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::expect_usage_errors;
using hydrolux::testing::run;

fs::path temp_dir() { return hydrolux::testing::temp_dir("hydrolux_render"); }

TEST(DropRenderCli, BuiltinEnvironmentToPngAndExr) {
  const auto dir = temp_dir();
  const auto png = dir / "drop.png", exr = dir / "drop.exr";
  auto r = run("drop render --size 48 --samples 2 -q -o " + png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto img = hydrolux::io::read_image(png);
  EXPECT_EQ(img.width, 48);
  EXPECT_EQ(img.height, 48);
  r = run("drop render --size 40 --samples 1 --dispersion --background-blur -q -o " + exr.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto e = hydrolux::io::read_image(exr);
  EXPECT_EQ(e.width, 40);
  // Linear radiance: the drop's centre shows the sky below the horizon, inverted; positive, finite.
  EXPECT_GT(e.at(20, 20, 2), 0.f);
  fs::remove_all(dir);
}

// An equirectangular file works as the environment: a uniform map of radiance 1 makes every
// background pixel 1 and the drop's centre the model's transfer R + S + P1 + P2 < 1.
TEST(DropRenderCli, EnvironmentFromFile) {
  const auto dir = temp_dir();
  hydrolux::Image env(64, 32, 3);
  for (auto& v : env.pixels) v = 1.f;
  hydrolux::io::write_image(dir / "uniform.exr", env);
  const auto out = dir / "drop.exr";
  const auto r = run("drop render --env " + (dir / "uniform.exr").string() + " --size 32 --samples 1 -q -o " +
                     out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto img = hydrolux::io::read_image(out);
  EXPECT_NEAR(img.at(0, 0, 0), 1.0, 1e-6);
  EXPECT_LT(img.at(16, 16, 0), 1.0);
  EXPECT_GT(img.at(16, 16, 0), 0.97);
  fs::remove_all(dir);
}

TEST(DropRenderCli, UsageErrors) {
  const auto dir = temp_dir();
  const std::string out = " -o " + (dir / "x.png").string();
  const std::string missing_env = " --env " + (dir / "nope.exr").string();
  hydrolux::io::write_image(dir / "square.exr", hydrolux::Image(16, 16, 3));  // not 2:1
  const std::pair<const char*, const char*> cases[] = {
      {"drop render", "--output"},
      {"drop render -o /tmp/x.jpg", "-o"},
      {"drop render -o /nonexistent-dir/x.png", "-o"},
  };
  expect_usage_errors(cases);
  const std::pair<std::string, const char*> more[] = {
      {"drop render --radius-mm 0" + out, "--radius-mm"},
      {"drop render --radius-mm abc" + out, "--radius-mm"},
      {"drop render --distance-m 0.0005" + out, "--distance-m"},
      {"drop render --size 0" + out, "--size"},
      {"drop render --samples 100" + out, "--samples"},
      {"drop render --wavelength-nm 5000" + out, "--wavelength-nm"},
      {"drop render --medium unobtainium" + out, "unobtainium"},
      {"drop render --env sky.jpg" + out, "--env"},
      {"drop render" + missing_env + out, "nope.exr"},
      {"drop render --method exact --shape beard-chuang --radius-mm 0.3" + out, "--radius-mm"},
      {"drop render --shape beard-chuang" + out, "--method exact"},
      {"drop render --background-blur --focal-mm 2000 --f-number 0.5 --distance-m 0.5" + out, "--focal-mm"},
      {"drop render --background-blur --focal-mm 200 --f-number 0.5 --distance-m 0.3" + out, "--background-blur"},
      {"drop render --medium const:0.9" + out, "--medium"},
      {"drop render --env " + (dir / "square.exr").string() + out, "--env"},
  };
  expect_usage_errors(more);
  EXPECT_FALSE(fs::exists(dir / "x.png"));  // nothing written on any error
  fs::remove_all(dir);
}

}  // namespace

namespace {

// The tool loads image support (OpenImageIO) from the plugin beside it only when a command needs
// it: without the plugin, commands without images still work and image commands fail in one line.
TEST(DropRenderCli, ImagePluginIsLoadedOnlyWhenNeeded) {
  const auto dir = hydrolux::testing::temp_dir("hydrolux_noplugin");
  const auto exe = dir / "hydrolux";
  fs::copy_file(HYDROLUX_CLI_PATH, exe, fs::copy_options::overwrite_existing);
  const auto run_copy = [&](const std::string& args) {
    const std::string cmd = exe.string() + " " + args + " 2>&1";
    std::string out;
    FILE* pipe = ::popen(cmd.c_str(), "r");
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
    const int status = ::pclose(pipe);
    return std::pair{WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
  };
  const auto [fresnel_code, fresnel_out] = run_copy("fresnel --n2 1.333 --theta-deg 10 --json");
  EXPECT_EQ(fresnel_code, 0) << fresnel_out;
  const auto [render_code, render_out] = run_copy("drop render --size 8 -q -o " + (dir / "x.png").string());
  EXPECT_EQ(render_code, 2);
  EXPECT_EQ(std::count(render_out.begin(), render_out.end(), '\n'), 1) << render_out;
  EXPECT_NE(render_out.find("libhydrolux_image_plugin.so"), std::string::npos) << render_out;
  EXPECT_FALSE(fs::exists(dir / "x.png"));
  fs::remove_all(dir);
}

}  // namespace
