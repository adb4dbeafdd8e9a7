// hydrolux sky's polariser and Stokes images end to end (docs/sky.md, "Polarisation"): from Stokes
// Lee tables given with --lut (hydrolux lee --stokes), the filter's frame at any angle equals the
// Stokes images' (I + Q cos 2A + U sin 2A) / 2; the Stokes images' I is the unfiltered frame; a
// table with the Stokes Q and one without give the same unfiltered frame byte for byte; what
// cannot work is refused with one line naming the flag, exit 2, nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "hydrolux/core/math.hpp"
#include "hydrolux/io/image_io.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::run;
using hydrolux::testing::slurp;
using namespace hydrolux;

// Two small rainbow tables by Airy theory, with and without the Stokes Q, computed once.
const fs::path& tables() {
  static const fs::path dir = [] {
    const fs::path d = hydrolux::testing::temp_dir("hydrolux_sky_polarizer_cli");
    for (const std::string stokes : {"", " --stokes"}) {
      const auto r = run("lee --theory airy --radius-um 200:800 --size 6x256 --sampling 0.25 -q" + stokes + " -o " +
                         (d / (stokes.empty() ? "plain.exr" : "stokes.exr")).string());
      EXPECT_EQ(r.code, 0) << r.err;
    }
    return d;
  }();
  return dir;
}

const std::string kScene = " --size 80x45 --radius-um 500 --sun-elevation-deg 10 --fov-deg 110 --view-elevation-deg 20 -q";

Image read(const fs::path& p) { return io::decode_image(slurp(p), p.string()).image; }

TEST(SkyPolarizerCli, FilterFramesFollowFromTheStokesImages) {
  const fs::path& d = tables();
  const std::string lut = " --lut " + (d / "stokes.exr").string();
  auto r = run("sky" + kScene + lut + " --stokes -o " + (d / "iqu.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Image iqu = read(d / "iqu.exr");
  ASSERT_EQ(iqu.channels, 9);
  r = run("sky" + kScene + lut + " -o " + (d / "none.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Image none = read(d / "none.exr");
  const std::size_t n = std::size_t(none.width) * none.height;
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(iqu.pixels[p * 9 + k], none.pixels[p * 3 + k]) << p;
  for (const double a : {0.0, 45.0, 90.0, -30.0}) {
    const fs::path out = d / ("a" + std::to_string(int(a + 100)) + ".exr");
    r = run("sky" + kScene + lut + " --polarizer-deg " + std::to_string(a) + " -o " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const Image f = read(out);
    const double c = std::cos(2 * a * kPi<double> / 180), s = std::sin(2 * a * kPi<double> / 180);
    double worst = 0;
    for (std::size_t p = 0; p < n; ++p)
      for (int k = 0; k < 3; ++k) {
        const float* v = &iqu.pixels[p * 9];
        const double expect = std::max(0.0, (v[k] + v[3 + k] * c + v[6 + k] * s) / 2);
        // float arithmetic in two orders (cos 2(chi - A) against cos 2chi cos 2A + ...): 1e-5.
        const double err = std::abs(f.pixels[p * 3 + k] - expect) / (v[k] + 1e-3);
        worst = std::max(worst, err);
      }
    EXPECT_LT(worst, 1e-5) << "A = " << a;
  }
  // The polarised part is real: the bow's top (Q > 0 tangential = horizontal there) has Q > 0.3 I.
  double best = 0;
  for (int j = 0; j < iqu.height; ++j) {
    const float* v = &iqu.pixels[(std::size_t(j) * iqu.width + iqu.width / 2) * 9];
    best = std::max(best, double(v[4]) / v[1]);
  }
  EXPECT_GT(best, 0.3);
}

TEST(SkyPolarizerCli, WithoutAFilterTheStokesTableChangesNothing) {
  const fs::path& d = tables();
  auto r = run("sky" + kScene + " --lut " + (d / "plain.exr").string() + " -o " + (d / "plain_sky.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("sky" + kScene + " --lut " + (d / "stokes.exr").string() + " -o " + (d / "stokes_sky.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(d / "plain_sky.exr"), slurp(d / "stokes_sky.exr"));
}

TEST(SkyPolarizerCli, RefusesWhatCannotWork) {
  const fs::path& d = tables();
  const fs::path out = d / "refused.exr";
  const auto refused = [&](const std::string& args, const std::string& flag) {
    const auto r = run("sky" + kScene + args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find(flag), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(d / "refused.png"));
  };
  // A table without the Stokes Q.
  refused(" --lut " + (d / "plain.exr").string() + " --polarizer-deg 0 -o " + out.string(), "--polarizer-deg");
  refused(" --lut " + (d / "plain.exr").string() + " --stokes -o " + out.string(), "--stokes");
  // The Stokes images need an EXR, the physical blend, and no filter.
  refused(" --lut " + (d / "stokes.exr").string() + " --stokes -o " + (d / "refused.png").string(), "--stokes");
  refused(" --lut " + (d / "stokes.exr").string() + " --stokes --blend whitepaper -o " + out.string(), "--stokes");
  refused(" --lut " + (d / "stokes.exr").string() + " --stokes --polarizer-deg 10 -o " + out.string(), "--stokes");
  // The sky's degree without anything that shows it.
  refused(" --lut " + (d / "stokes.exr").string() + " --sky-max-dolp 0.5 -o " + out.string(), "--sky-max-dolp");
  refused(" --lut " + (d / "stokes.exr").string() + " --polarizer-deg 181 -o " + out.string(), "--polarizer-deg");
}

}  // namespace
