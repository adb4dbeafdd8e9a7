// hydrolux lens-drops end to end: the output and its mask (clean where the mask is 0, the mask in
// [0, 1] and covering some of the frame), the same seed giving the same bytes, the input never
// touched, a folder of frames with its masks, and bad values refused in one line naming the flag
// with nothing written (tests/cli/robustness_cases.txt runs every flag's bad values).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hydrolux/io/image_io.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::run;
using hydrolux::testing::slurp;
using namespace hydrolux;

fs::path dir() {
  static const fs::path d = hydrolux::testing::temp_dir("hydrolux_lens_drops_cli");
  return d;
}

const fs::path& clean_exr() {
  static const fs::path p = hydrolux::testing::builtin_frame(dir() / "clean.exr", "320x180");
  return p;
}

TEST(LensDropsCli, ImageAndMask) {
  const fs::path out = dir() / "drops.exr", mask = dir() / "mask.exr";
  const std::string before = slurp(clean_exr());
  const auto r = run("lens-drops --image " + clean_exr().string() + " --seed 4 -o " + out.string() + " --mask-out " +
                     mask.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("lens-drops: 1 frame;"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(clean_exr()), before);
  const Image c = io::read_image(clean_exr()), o = io::read_image(out), m = io::read_image(mask);
  ASSERT_EQ(m.channels, 1);
  ASSERT_EQ(o.width, c.width);
  ASSERT_EQ(o.height, c.height);
  double covered = 0;
  int clear = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const float a = m.at(x, y, 0);
      ASSERT_GE(a, 0.f);
      ASSERT_LE(a, 1.f);
      covered += a;
      if (a == 0) {
        ++clear;
        for (int k = 0; k < 3; ++k) ASSERT_EQ(o.at(x, y, k), c.at(x, y, k)) << x << "," << y;
      }
    }
  const double frac = covered / (c.width * c.height);
  EXPECT_GT(frac, 0.02);
  EXPECT_LT(frac, 0.9);
  EXPECT_GT(clear, 0);
}

TEST(LensDropsCli, SameSeedSameBytes) {
  const fs::path a = dir() / "a.png", b = dir() / "b.png", c = dir() / "c.png";
  const std::string base = "lens-drops -q --image " + clean_exr().string() + " --coverage 0.15 ";
  ASSERT_EQ(run(base + "--seed 11 -o " + a.string()).code, 0);
  ASSERT_EQ(run(base + "--seed 11 -o " + b.string()).code, 0);
  ASSERT_EQ(run(base + "--seed 12 -o " + c.string()).code, 0);
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_NE(slurp(a), slurp(c));
}

TEST(LensDropsCli, FolderOfFramesWithMasks) {
  const fs::path in = dir() / "frames", out = dir() / "out", masks = dir() / "masks";
  fs::create_directories(in);
  fs::copy_file(clean_exr(), in / "f0.exr", fs::copy_options::overwrite_existing);
  fs::copy_file(clean_exr(), in / "f1.exr", fs::copy_options::overwrite_existing);
  const auto r = run("lens-drops -q --input-dir " + in.string() + " --output-dir " + out.string() + " --mask-dir " +
                     masks.string() + " --seed 5");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* n : {"f0.exr", "f1.exr"}) {
    EXPECT_TRUE(fs::is_regular_file(out / n)) << n;
    EXPECT_TRUE(fs::is_regular_file(masks / n)) << n;
  }
  // Frame k has the drops of seed + k: the second frame's are the first frame's of seed 6.
  EXPECT_NE(slurp(masks / "f0.exr"), slurp(masks / "f1.exr"));
  const fs::path single = dir() / "single6.exr";
  ASSERT_EQ(run("lens-drops -q --image " + clean_exr().string() + " --seed 6 -o " + single.string()).code, 0);
  EXPECT_EQ(slurp(single), slurp(out / "f1.exr"));
}

// A frame that cannot be read is named and left out once a frame is written, as rain and fog do:
// exit 1, the others written; a bad first frame is bad input: exit 2, nothing written.
TEST(LensDropsCli, BadFrameLeftOutOthersWritten) {
  const fs::path in = dir() / "bad_frames", out = dir() / "bad_out";
  fs::create_directories(in);
  fs::copy_file(clean_exr(), in / "f0.exr", fs::copy_options::overwrite_existing);
  {
    std::ofstream f(in / "f1.exr");
    f << "not an image";
  }
  fs::copy_file(clean_exr(), in / "f2.exr", fs::copy_options::overwrite_existing);
  auto r = run("lens-drops -q --input-dir " + in.string() + " --output-dir " + out.string() + " --seed 5");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("1 of 3 frames left out (f1.exr); the others are written"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_regular_file(out / "f0.exr"));
  EXPECT_FALSE(fs::exists(out / "f1.exr"));
  EXPECT_TRUE(fs::is_regular_file(out / "f2.exr"));
  // Frame 2 keeps its seed + 2 whatever frame 1 did.
  const fs::path single = dir() / "single7.exr";
  ASSERT_EQ(run("lens-drops -q --image " + clean_exr().string() + " --seed 7 -o " + single.string()).code, 0);
  EXPECT_EQ(slurp(single), slurp(out / "f2.exr"));
  const fs::path in2 = dir() / "bad_first", out2 = dir() / "bad_first_out";
  fs::create_directories(in2);
  fs::copy_file(in / "f1.exr", in2 / "a.exr", fs::copy_options::overwrite_existing);
  fs::copy_file(clean_exr(), in2 / "b.exr", fs::copy_options::overwrite_existing);
  r = run("lens-drops -q --input-dir " + in2.string() + " --output-dir " + out2.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_FALSE(fs::exists(out2 / "b.exr"));
}

TEST(LensDropsCli, BadValuesAreOneLineNamingTheFlag) {
  const fs::path out = dir() / "never.png";
  const std::string base = "lens-drops --image " + clean_exr().string() + " -o " + out.string() + " ";
  for (const auto& [args, flag] : std::initializer_list<std::pair<std::string, std::string>>{
           {"--contact-angle-deg 100", "--contact-angle-deg"},
           {"--min-radius-mm 3 --max-radius-mm 1", "--max-radius-mm"},
           {"--drops 5 --coverage 0.1", "--coverage"},
           {"--focal-mm 50 --focus-m 0.02", "--focus-m"}}) {
    const auto r = run(base + args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(hydrolux::testing::lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty());
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

}  // namespace
