// io::run_rain_job over a folder of frames or a video (issue 27): the read, render and write of
// neighbouring frames overlap on three threads; the files must be those of one frame at a time, whatever the
// number of threads, a frame that cannot be used left out as before, and a bad first frame still
// stops the run with nothing written.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/io/rain_job.hpp"
#include "hydrolux/io/video.hpp"
#include "hydrolux/rain/params.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::io {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 160, kHeight = 90, kFrames = 7;

class RainJobFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hydrolux_test_rain_job_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "in");
    rain::RainCamera cam;
    cam.width = kWidth;
    cam.height = kHeight;
    const Image scene = rain::builtin_scene(cam);
    for (int k = 0; k < kFrames; ++k) {
      Image f = scene;
      for (float& v : f.pixels) v *= 1.0f + 0.05f * float(k);  // each frame its own
      write_file(dir_ / "in" / name(k), encode_image(f, ImageFormat::png, {8, 6}));
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string name(int k) {
    char s[16];
    std::snprintf(s, sizeof s, "f%d.png", k);
    return s;
  }

  RainJob job(const std::string& out) const {
    RainJob j;
    j.input_dir = (dir_ / "in").string();
    j.output_dir = (dir_ / out).string();
    j.mask_dir = (dir_ / (out + "_masks")).string();
    j.options.settings.rain_rate_mmh = 25;
    j.options.settings.wind_mps = 3;
    j.options.settings.seed = 4;
    j.files.frame_index = 10;
    return j;
  }

  RainJobResult run(const RainJob& j, std::vector<std::string>* warnings = nullptr) const {
    RainJobHooks h;
    h.codec = {&decode_image, &encode_image};
    h.warn = [warnings](const std::string& w) {
      if (warnings) warnings->push_back(w);
    };
    return run_rain_job(j, h);
  }

  // What one frame at a time writes: each readable frame rendered in order by one renderer (frame
  // index frame_index + k) and encoded as the job encodes.
  std::map<std::string, std::string> one_at_a_time(const RainJob& j, int skipped = -1) const {
    std::map<std::string, std::string> files;
    const rain::RainCamera cam = rain::camera_for(j.options, kWidth, kHeight);
    rain::RainRenderer r(rain::RainField(j.options.settings, cam, true));
    rain::RainFrame out;
    const PngOptions png{8, j.files.png_compression}, png16{16, j.files.png_compression};
    for (int k = 0; k < kFrames; ++k) {
      if (k == skipped) continue;
      const Image frame = decode_image(read_file(dir_ / "in" / name(k)), name(k)).image;
      r.render_into(frame, nullptr, j.files.frame_index + k, false, out);
      files["out/" + name(k)] = encode_image(out.image, ImageFormat::png, png);
      files["out_masks/" + name(k)] = encode_image(coverage_for_encoding(out.alpha, ImageFormat::png), ImageFormat::png, png16);
    }
    return files;
  }

  // Every file the run wrote, under names relative to out/ and out_masks/.
  std::map<std::string, std::string> written(const std::string& out) const {
    std::map<std::string, std::string> files;
    for (const std::string& folder : {out, out + "_masks"}) {
      if (!fs::exists(dir_ / folder)) continue;
      for (const auto& e : fs::directory_iterator(dir_ / folder))
        files[(folder == out ? std::string("out/") : std::string("out_masks/")) + e.path().filename().string()] =
            read_file(e.path());
    }
    return files;
  }

  fs::path dir_;
};

// The deterministic-bytes promise: on one thread or on every core (the renderer's loops; the
// pipeline's three stages are threads of their own either way), the files are those of one frame at
// a time, and frames are written in order with their statistics.
TEST_F(RainJobFolder, OverlappedRunWritesTheBytesOfOneFrameAtATime) {
  for (int level : {1, 6}) {
    for (std::size_t threads : {std::size_t(1), std::size_t(2), std::size_t(8)}) {
      const std::string out = "out" + std::to_string(level) + "_" + std::to_string(threads);
      RainJob j = job(out);
      j.files.png_compression = level;
      j.stats_json = (dir_ / (out + ".json")).string();
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const RainJobResult r = run(j);
      EXPECT_EQ(r.frames, std::size_t(kFrames));
      EXPECT_TRUE(r.left_out.empty());
      auto expected = one_at_a_time(j);
      auto got = written(out);
      ASSERT_EQ(got.size(), expected.size()) << out;
      for (const auto& [file, bytes] : expected) EXPECT_TRUE(got[file] == bytes) << out << " " << file;
      const std::string stats = read_file(*j.stats_json);
      std::size_t at = 0;
      for (int k = 0; k < kFrames; ++k) {  // in order
        const std::size_t next = stats.find("\"" + name(k) + "\"", at);
        ASSERT_NE(next, std::string::npos) << name(k);
        at = next;
      }
    }
  }
}

// A frame that cannot be read after the first is left out, named, and the others are the bytes of one
// frame at a time (the rain of each frame is its own: frame k at frame_index + k either way).
TEST_F(RainJobFolder, AFrameThatCannotBeReadIsLeftOutAndTheOthersWritten) {
  const std::string whole = read_file(dir_ / "in" / name(3));
  { write_file(dir_ / "in" / name(3), whole.substr(0, whole.size() / 2)); }
  for (std::size_t threads : {std::size_t(1), std::size_t(2)}) {
    const std::string out = "out_" + std::to_string(threads);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    std::vector<std::string> warnings;
    const RainJob j = job(out);
    const RainJobResult r = run(j, &warnings);
    EXPECT_EQ(r.frames, std::size_t(kFrames - 1));
    EXPECT_EQ(r.left_out, std::vector<std::string>{name(3)});
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(name(3)), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("(left out)"), std::string::npos) << warnings[0];
    auto expected = one_at_a_time(j, 3);
    auto got = written(out);
    ASSERT_EQ(got.size(), expected.size());
    for (const auto& [file, bytes] : expected) EXPECT_TRUE(got[file] == bytes) << file;
  }
}

// A first frame that cannot be read is bad input: the error, nothing written (no frame, no mask, no
// statistics), however far the reader had got meanwhile.
TEST_F(RainJobFolder, ABadFirstFrameStopsTheRunWithNothingWritten) {
  const std::string whole = read_file(dir_ / "in" / name(0));
  write_file(dir_ / "in" / name(0), whole.substr(0, whole.size() / 2));
  RainJob j = job("out");
  j.stats_json = (dir_ / "stats.json").string();
  try {
    (void)run(j);
    ADD_FAILURE() << "no error";
  } catch (const IoFailure& e) {
    ADD_FAILURE() << e.what();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(name(0)), std::string::npos) << e.what();
  }
  EXPECT_TRUE(written("out").empty());
  EXPECT_FALSE(fs::exists(dir_ / "stats.json"));
  EXPECT_EQ(pending_output_count(), 0u);
}

// The level is checked where the job is: a level outside 0-9 is refused before any frame is written.
TEST_F(RainJobFolder, APngCompressionLevelOutsideTheRangeIsRefused) {
  const auto& p = rain::rain_param("png_compression");
  EXPECT_EQ(p.flag, std::string("--png-compression"));
  EXPECT_EQ(p.lo, 0);
  EXPECT_EQ(p.hi, kMaxPngCompression);
  EXPECT_EQ(rain::RainFileOptions{}.png_compression, kDefaultPngCompression);
  RainJob j = job("out");
  j.files.png_compression = 10;
  EXPECT_THROW((void)run(j), Error);
  EXPECT_TRUE(written("out").empty());
}

// A video's frames overlap the same way (decode, render and encode on three threads): the output
// is the bytes of one frame at a time, decoded, rendered and encoded in order, on one thread or two.
TEST_F(RainJobFolder, OverlappedVideoWritesTheBytesOfOneFrameAtATime) {
  const fs::path in = dir_ / "in.mp4";
  const std::string make = "ffmpeg -v error -y -f lavfi -i testsrc2=size=160x96:rate=25 -frames:v 9 -pix_fmt yuv420p "
                           "-c:v libx264 " + in.string();
  ASSERT_EQ(std::system(make.c_str()), 0) << "ffmpeg (Debian's ffmpeg package; scripts/install-deps)";
  RainJob j;
  j.video = in.string();
  j.options.settings.rain_rate_mmh = 25;
  j.options.settings.wind_mps = 3;
  j.options.settings.seed = 4;
  j.files.frame_index = 10;

  // One frame at a time: read, render, encode, in order, on this thread.
  const VideoApi& api = video_api();
  const std::string bytes = read_file(in);
  auto reader = api.open_reader(
      [&bytes](std::uint64_t off, char* buf, std::size_t n) {
        const std::size_t got = off < bytes.size() ? std::min<std::size_t>(n, bytes.size() - std::size_t(off)) : 0;
        std::memcpy(buf, bytes.data() + off, got);
        return got;
      },
      bytes.size(), "in.mp4", VideoLimits{});
  std::string expected;
  auto writer = api.open_writer(
      [&expected](std::uint64_t off, std::string_view b) {
        if (expected.size() < off + b.size()) expected.resize(std::size_t(off) + b.size());
        std::memcpy(expected.data() + off, b.data(), b.size());
      },
      ".mp4", reader->info(), j.files.crf, "expected.mp4");
  rain::RainCamera cam = rain::camera_for(j.options, reader->info().width, reader->info().height);
  cam.fps = reader->info().fps();
  rain::RainRenderer r(rain::RainField(j.options.settings, cam, true));
  const color::Srgb8Tables tables;
  VideoFrame frame, out_frame;
  rain::RainFrame out;
  int frames = 0;
  for (; reader->read(frame); ++frames) {
    Image linear(frame.width, frame.height, 3);
    tables.to_linear(frame.rgb.data(), std::size_t(frame.width) * frame.height, linear.pixels.data());
    r.render_into(linear, nullptr, j.files.frame_index + frames, false, out);
    out_frame.width = frame.width;
    out_frame.height = frame.height;
    out_frame.rgb.resize(frame.rgb.size());
    tables.to_srgb8(out.image.pixels.data(), std::size_t(frame.width) * frame.height, out.image.channels,
                    out_frame.rgb.data());
    writer->write(out_frame);
  }
  writer->finish();
  ASSERT_EQ(frames, 9);

  for (std::size_t threads : {std::size_t(1), std::size_t(2)}) {
    const fs::path o = dir_ / ("out_" + std::to_string(threads) + ".mp4");
    j.output = o.string();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const RainJobResult res = run(j);
    EXPECT_EQ(res.frames, 9u);
    EXPECT_TRUE(read_file(o) == expected) << threads << " threads";
  }
}

}  // namespace
}  // namespace hydrolux::io
