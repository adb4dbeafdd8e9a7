// Every effect of the frame driver (io/frame_driver.hpp) has the video mode and the same files and
// refusals as `hydrolux rain --video`: `hydrolux fog --video` keeps the frame count and rate and one
// sky colour for the whole video (the first frame's); `hydrolux lens-drops --video` gives frame k the
// drops of --seed + k; the flags a video does not use are refused in one line, nothing written.
// Small synthetic videos (64 x 48, a few frames) made with Debian's ffmpeg.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hydrolux/rain/params.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::run;
using hydrolux::testing::ffprobe_csv;
using hydrolux::testing::slurp;

fs::path dir() {
  static const fs::path d = hydrolux::testing::temp_dir("hydrolux_frame_video");
  return d;
}

// Five frames of 64 x 48 at 25/1 frames/s, fading out: each frame darker than the one before, so
// that a sky colour estimated anew for each frame would differ from frame to frame.
const fs::path& fading_video() {
  static const fs::path p = [] {
    const fs::path f = dir() / "fading.mp4";
    const std::string make = "ffmpeg -nostdin -v error -y -f lavfi -i testsrc2=size=64x48:rate=25 -frames:v 5 "
                             "-vf fade=t=out:st=0:d=0.2 -pix_fmt yuv420p -c:v libx264 " + f.string();
    EXPECT_EQ(std::system(make.c_str()), 0) << "ffmpeg (Debian's ffmpeg package; scripts/install-deps)";
    return f;
  }();
  return p;
}

TEST(FrameVideo, FogKeepsFramesRateAndTheFirstFramesSky) {
  const fs::path out = dir() / "fog.mp4", stats = dir() / "fog.json";
  const std::string before = slurp(fading_video());
  const auto r = run("fog -q --video " + fading_video().string() + " --visibility-m 150 --crf 23 -o " + out.string() +
                     " --stats-json " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_EQ(slurp(fading_video()), before);  // the input is never modified
  EXPECT_EQ(ffprobe_csv(out), "64,48,25/1,5\n");
  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(j.at("input"), fading_video().string());
  EXPECT_EQ(j.at("video").at("frames"), 5);
  EXPECT_EQ(j.at("video").at("crf"), 23);
  EXPECT_EQ(j.at("camera").at("width"), 64);
  const auto& frames = j.at("frames");
  ASSERT_EQ(frames.size(), 5u);
  // One sky for the video, the first frame's, though the frames grow darker.
  const auto sky = frames.at(0).at("sky_rgb");
  EXPECT_GT(double(sky.at(0)) + double(sky.at(1)) + double(sky.at(2)), 0.0);
  for (const auto& f : frames) {
    EXPECT_EQ(f.at("sky_rgb"), sky);
    EXPECT_LT(double(f.at("transmittance").at("mean")), 1.0);
  }
  // The same fog over the last frame alone estimates its own, darker sky: the sky above is kept, not
  // found again.
  const fs::path last = dir() / "last.png", last_stats = dir() / "last.json";
  ASSERT_EQ(std::system(("ffmpeg -nostdin -v error -y -i " + fading_video().string() +
                         " -vf 'select=eq(n\\,4)' -frames:v 1 " + last.string()).c_str()),
            0);
  ASSERT_EQ(run("fog -q --image " + last.string() + " --visibility-m 150 -o " + (dir() / "last_fog.png").string() +
                " --stats-json " + last_stats.string())
                .code,
            0);
  const auto own = nlohmann::json::parse(slurp(last_stats)).at("frames").at(0).at("sky_rgb");
  EXPECT_LT(double(own.at(0)) + double(own.at(1)) + double(own.at(2)),
            0.5 * (double(sky.at(0)) + double(sky.at(1)) + double(sky.at(2))));
}

TEST(FrameVideo, LensDropsGiveFrameKTheDropsOfSeedPlusK) {
  const fs::path out = dir() / "lens.mkv", stats = dir() / "lens.json";
  const auto r = run("lens-drops -q --video " + fading_video().string() + " --seed 40 --drops 30 -o " + out.string() +
                     " --stats-json " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_EQ(ffprobe_csv(out), "64,48,25/1,5\n");
  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(j.at("drops").at("seed"), 40);
  const auto& frames = j.at("frames");
  ASSERT_EQ(frames.size(), 5u);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(frames.at(k).at("seed"), 40 + int(k));
    EXPECT_GT(double(frames.at(k).at("coverage")), 0.0);
  }
  // Each frame its own drops: the coverage differs from frame to frame.
  EXPECT_NE(frames.at(0).at("coverage"), frames.at(1).at("coverage"));
}

TEST(FrameVideo, FlagsAVideoDoesNotUseAreRefusedInOneLine) {
  const std::string v = " --video " + fading_video().string(), o = " -o " + (dir() / "never.mp4").string();
  const std::string img = " --image " + (dir() / "last.png").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"fog" + v + " --visibility-m 100 --depth " + (dir() / "d.exr").string() + o, "--depth"},
      {"fog" + v + " --visibility-m 100 --mask-out " + (dir() / "m.png").string() + o, "--video"},
      {"fog" + v + " --visibility-m 100 --depth-scale-m 0.01" + o, "--depth-scale-m"},
      {"fog" + v + " --visibility-m 100 -o " + (dir() / "never.png").string(), "-o"},
      {"fog" + v + " --visibility-m 100", "-o"},
      {"fog" + v + " --visibility-m 100 --crf 52" + o, "--crf"},
      {"fog" + v + img + " --visibility-m 100" + o, "--image"},
      {"fog" + v + o, "--visibility-m"},
      {"fog --image " + fading_video().string() + " --visibility-m 100 --crf 20 -o " + (dir() / "n.png").string(),
       "--crf"},
      {"lens-drops" + v + " --mask-dir " + (dir() / "masks").string() + o, "--mask-dir"},
      {"lens-drops" + v + " --output-dir " + (dir() / "outs").string() + o, "--output-dir"},
      {"lens-drops" + v + " -o " + (dir() / "never.avi").string(), "-o"},
      {"lens-drops" + v + " --contact-angle-deg 100" + o, "--contact-angle-deg"},
      {"lens-drops --video " + (dir() / "missing.mp4").string() + o, "--video"},
      {"lens-drops --input-dir " + dir().string() + " --output-dir " + (dir() / "outs").string() + " --crf 20", "--crf"},
  };
  hydrolux::testing::expect_usage_errors(cases);
  EXPECT_FALSE(fs::exists(dir() / "never.mp4"));
  EXPECT_FALSE(fs::exists(dir() / "outs"));
  EXPECT_FALSE(fs::exists(dir() / "masks"));
}

// Where a file parameter has an effect is the library's table (Param::only_with, not_with), read by the
// driver for every effect and door: --crf only with --video, --depth-scale-m only with depth maps, rain's
// --fps not with a video. The refusal is one line in ParamUse's format, the value as given, the reason
// from the table (the texts below are the declared ones, written out).
TEST(FrameVideo, WhereAFileParameterHasAnEffectIsTheTables) {
  EXPECT_EQ(hydrolux::rain::rain_param("crf").only_with, "video");
  EXPECT_EQ(hydrolux::rain::rain_param("depth_scale_m").only_with, "depth|depth_dir");
  EXPECT_EQ(hydrolux::rain::rain_param("fps").not_with, "video");
  const std::string v = " --video " + fading_video().string(), png = " -o " + (dir() / "never.png").string();
  const std::string crf = ": --crf 20: sets the H.264 quality of --video's output; pictures have none\n";
  const std::string scale = ": --depth-scale-m 0.01: scales the codes of PNG depth maps; none is given\n";
  const std::pair<std::string, std::string> cases[] = {
      {"fog --image " + (dir() / "last.png").string() + " --visibility-m 100 --crf 20" + png, "hydrolux fog" + crf},
      {"lens-drops --image " + (dir() / "last.png").string() + " --crf 20" + png, "hydrolux lens-drops" + crf},
      {"rain --image builtin --size 32x24 --crf 20" + png, "hydrolux rain" + crf},
      {"rain --image builtin --size 32x24 --depth-scale-m 0.01" + png, "hydrolux rain" + scale},
      {"fog" + v + " --visibility-m 100 --depth-scale-m 0.01 -o " + (dir() / "never.mp4").string(), "hydrolux fog" + scale},
      {"rain" + v + " --fps 30 -o " + (dir() / "never.mp4").string(),
       "hydrolux rain: --fps 30: a video's frame rate is its own\n"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(r.err, message) << args;
  }
  EXPECT_FALSE(fs::exists(dir() / "never.png"));
  EXPECT_FALSE(fs::exists(dir() / "never.mp4"));
}

}  // namespace
