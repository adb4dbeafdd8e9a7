// The video plugin (hydrolux/io/video.hpp) as the CLI uses it: loaded with video_api()
// from beside the test executable (build/bin, where the plugin is built), reading through
// io::InputFile and writing through io::OutputFile::write_at. Test videos are made, and the plugin's
// output checked, with Debian's ffmpeg and ffprobe (scripts/install-deps installs them).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/video.hpp"
#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::Error;
using hydrolux::IoError;
using hydrolux::IoFailure;
using hydrolux::io::video_api;
using hydrolux::io::VideoFrame;
using hydrolux::io::VideoInfo;
using hydrolux::io::VideoLimits;
using hydrolux::io::VideoReader;
using hydrolux::io::VideoWriter;

fs::path temp_dir() { return hydrolux::testing::temp_dir("hydrolux_video"); }

// Runs a shell command; returns its stdout, and fails the test on a non-zero exit.
std::string shell(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) {
    ADD_FAILURE() << "cannot run: " << command;
    return out;
  }
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command << "\n" << out;
  return out;
}

void ffmpeg(const std::string& args) { shell("ffmpeg -nostdin -v error -y " + args + " 2>&1"); }

// ffprobe's view of the first video stream, frames counted by decoding: width, height,
// r_frame_rate, nb_read_frames.
std::map<std::string, std::string> probe(const fs::path& file) {
  const std::string out = shell(
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=nb_read_frames,r_frame_rate,width,height -of default=noprint_wrappers=1 '" +
      file.string() + "'");
  std::map<std::string, std::string> m;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);)
    if (const auto eq = line.find('='); eq != std::string::npos) m[line.substr(0, eq)] = line.substr(eq + 1);
  return m;
}

std::unique_ptr<VideoReader> open(const hydrolux::io::InputFile& in, const VideoLimits& limits = {}) {
  return video_api().open_reader(
      [&in](std::uint64_t offset, char* buffer, std::size_t size) { return in.read_at(offset, buffer, size); },
      in.size(), in.path().string(), limits);
}

// A file opened as the CLI opens it: the InputFile and its reader, which reads through it.
struct Opened {
  std::unique_ptr<hydrolux::io::InputFile> in;
  std::unique_ptr<VideoReader> reader;
  VideoReader* operator->() const { return reader.get(); }
  VideoReader& operator*() const { return *reader; }
};

Opened open(const fs::path& file, const VideoLimits& limits = {}) {
  Opened o;
  o.in = std::make_unique<hydrolux::io::InputFile>(file);
  o.reader = open(*o.in, limits);
  return o;
}

std::vector<VideoFrame> read_all(VideoReader& reader) {
  std::vector<VideoFrame> frames;
  VideoFrame f;
  while (reader.read(f)) frames.push_back(f);
  EXPECT_FALSE(reader.read(f));  // stays at the end
  return frames;
}

// A smooth moving gradient: what H.264 keeps well, so the round trip error is small and stable.
VideoFrame gradient(int w, int h, int k) {
  VideoFrame f;
  f.width = w;
  f.height = h;
  f.rgb.resize(std::size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto* p = &f.rgb[(std::size_t(y) * w + x) * 3];
      p[0] = std::uint8_t(std::lround(40 + 170.0 * x / (w - 1)));
      p[1] = std::uint8_t(std::lround(40 + 170.0 * y / (h - 1)));
      p[2] = std::uint8_t(std::lround(128 + 60 * std::sin(2 * std::numbers::pi * (double(x) / w + k / 30.0))));
    }
  return f;
}

double mean_abs_difference(const VideoFrame& a, const VideoFrame& b) {
  EXPECT_EQ(a.rgb.size(), b.rgb.size());
  if (a.rgb.size() != b.rgb.size() || a.rgb.empty()) return 1e9;
  double sum = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) sum += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
  return sum / double(a.rgb.size());
}

// Writes `frames` through open_writer into `file` (an OutputFile, committed); returns the bytes.
std::string write_video(const fs::path& file, const std::vector<VideoFrame>& frames, int fps_num, int fps_den,
                        int crf = 18) {
  hydrolux::io::OutputFile out(file, "-o");
  VideoInfo info;
  info.width = frames.at(0).width;
  info.height = frames.at(0).height;
  info.fps_num = fps_num;
  info.fps_den = fps_den;
  {
    auto writer = video_api().open_writer(
        [&out](std::uint64_t offset, std::string_view bytes) { out.write_at(offset, bytes); },
        file.extension().string(), info, crf, "-o " + file.string());
    for (const auto& f : frames) writer->write(f);
    writer->finish();
  }
  out.commit();
  return hydrolux::testing::slurp(file);
}

void expect_one_line_naming(const std::string& message, const std::string& origin) {
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind(origin, 0), 0u) << message;
}

template <typename F>
void expect_io_error(F&& f, const std::string& origin, const std::string& contains = {}) {
  try {
    f();
    ADD_FAILURE() << "no IoError for " << origin;
  } catch (const IoError& e) {
    expect_one_line_naming(e.what(), origin);
    if (!contains.empty()) {
      EXPECT_NE(std::string(e.what()).find(contains), std::string::npos) << e.what();
    }
  }
}

TEST(Video, ReadsWhatFfmpegWrites) {
  const auto dir = temp_dir();
  const auto mp4 = dir / "x.mp4";
  ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=25 -frames:v 30 -pix_fmt yuv420p -c:v libx264 '" + mp4.string() + "'");
  auto reader = open(mp4);
  const VideoInfo& info = reader->info();
  EXPECT_EQ(info.width, 96);
  EXPECT_EQ(info.height, 64);
  EXPECT_EQ(info.fps_num, 25);
  EXPECT_EQ(info.fps_den, 1);
  EXPECT_EQ(info.frame_count, 30);
  EXPECT_EQ(info.codec, "h264");
  EXPECT_NEAR(info.duration_s, 1.2, 0.05);
  const auto frames = read_all(*reader);
  ASSERT_EQ(frames.size(), 30u);
  for (const auto& f : frames) {
    EXPECT_EQ(f.width, 96);
    EXPECT_EQ(f.height, 64);
    EXPECT_EQ(f.rgb.size(), 96u * 64u * 3u);
  }
  // testsrc2 moves: consecutive frames differ.
  EXPECT_GT(mean_abs_difference(frames[0], frames[1]), 0.5);

  // 10-bit H.264 in Matroska, which also states no frame count.
  const auto mkv = dir / "x10.mkv";
  ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=25 -frames:v 12 -pix_fmt yuv420p10le -c:v libx264 '" + mkv.string() +
         "'");
  auto reader10 = open(mkv);
  EXPECT_EQ(reader10->info().frame_count, -1);
  const auto frames10 = read_all(*reader10);
  ASSERT_EQ(frames10.size(), 12u);
  // The same picture as the 8-bit file's first frame, but for coding noise.
  EXPECT_LT(mean_abs_difference(frames10[0], frames[0]), 3.0);
  fs::remove_all(dir);
}

// Y'CbCr of a flat picture (exact: x264 at CRF 0 is lossless), tagged three ways; the RGB that comes
// out must follow each stream's matrix and range (ITU-R BT.709 / BT.601, limited or full), and an
// untagged standard-definition stream is read as BT.601, limited range, as players do.
TEST(Video, HonoursTheStreamsColourMatrixAndRange) {
  const auto dir = temp_dir();
  const int w = 64, h = 48, Y = 120, Cb = 140, Cr = 100;
  {
    std::string yuv(std::size_t(w) * h, char(Y));
    yuv += std::string(std::size_t(w) * h / 4, char(Cb));
    yuv += std::string(std::size_t(w) * h / 4, char(Cr));
    std::ofstream(dir / "flat.yuv", std::ios::binary) << yuv << yuv << yuv;
  }
  struct Case {
    const char* name;
    const char* input_format;
    const char* tags;
    double kr, kb;
    bool full;
  };
  const Case cases[] = {
      {"bt709-tv.mp4", "yuv420p", "-colorspace bt709 -color_range tv", 0.2126, 0.0722, false},
      {"bt601-pc.mp4", "yuvj420p", "-colorspace smpte170m -color_range pc", 0.299, 0.114, true},
      {"untagged.mkv", "yuv420p", "", 0.299, 0.114, false},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto file = dir / c.name;
    ffmpeg(std::string("-f rawvideo -pix_fmt ") + c.input_format + " -s 64x48 -r 25 -i '" +
           (dir / "flat.yuv").string() + "' -c:v libx264 -crf 0 " + c.tags + " '" + file.string() + "'");
    const double y = c.full ? Y / 255.0 : (Y - 16) / 219.0;
    const double pb = (Cb - 128) / (c.full ? 255.0 : 224.0), pr = (Cr - 128) / (c.full ? 255.0 : 224.0);
    const double r = y + 2 * (1 - c.kr) * pr, b = y + 2 * (1 - c.kb) * pb;
    const double g = (y - c.kr * r - c.kb * b) / (1 - c.kr - c.kb);
    const double expected[3] = {255 * r, 255 * g, 255 * b};
    const auto frames = read_all(*open(file));
    ASSERT_EQ(frames.size(), 3u);
    for (int ch = 0; ch < 3; ++ch) {
      double sum = 0;
      for (std::size_t i = std::size_t(ch); i < frames[0].rgb.size(); i += 3) sum += frames[0].rgb[i];
      // Within a level of the exact value: 8-bit output, rounded. The three cases differ from each
      // other by 5 levels or more in some channel.
      EXPECT_NEAR(sum / (w * h), expected[ch], 1.0) << "channel " << ch;
    }
  }
  fs::remove_all(dir);
}

TEST(Video, WritesWhatFfmpegAndTheReaderRead) {
  const auto dir = temp_dir();
  const int w = 96, h = 64;
  std::vector<VideoFrame> frames;
  for (int k = 0; k < 30; ++k) frames.push_back(gradient(w, h, k));

  for (const char* name : {"out.mp4", "out.mov", "out.mkv"}) {
    SCOPED_TRACE(name);
    const auto file = dir / name;
    const std::string bytes = write_video(file, frames, 25, 1);
    const auto p = probe(file);
    EXPECT_EQ(p.at("width"), "96");
    EXPECT_EQ(p.at("height"), "64");
    EXPECT_EQ(p.at("r_frame_rate"), "25/1");
    EXPECT_EQ(p.at("nb_read_frames"), "30");
    EXPECT_EQ(shell("ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,pix_fmt,color_space,"
                    "color_range -of csv=p=0 '" + file.string() + "'"),
              "h264,yuv420p,tv,bt709\n");

    auto reader = open(file);
    EXPECT_EQ(reader->info().width, w);
    EXPECT_EQ(reader->info().height, h);
    EXPECT_EQ(reader->info().fps_num, 25);
    EXPECT_EQ(reader->info().fps_den, 1);
    const auto back = read_all(*reader);
    ASSERT_EQ(back.size(), frames.size());
    double worst = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) worst = std::max(worst, mean_abs_difference(frames[i], back[i]));
    // H.264 at CRF 18 is visually lossless: on a smooth gradient its quantisation costs about a
    // level; 4:2:0 chroma (one Cb, Cr per 2 x 2 pixels) costs a fraction of a level where colour
    // changes slowly; the two 8-bit YUV <-> RGB conversions round twice (half a level each at
    // most). 3 levels bounds their sum with room to spare while catching any colour-matrix,
    // range, frame-order or off-by-one-frame mistake (each costs 5 levels or more here).
    EXPECT_LT(worst, 3.0);

    // The same frames give the same bytes (fixed encoder thread count, bit-exact muxing).
    const std::string again = write_video(dir / (std::string("again-") + name), frames, 25, 1);
    EXPECT_TRUE(again == bytes) << again.size() << " bytes the second time, " << bytes.size() << " the first";
  }

  // A non-integer rate is kept exactly.
  const auto ntsc = dir / "ntsc.mp4";
  write_video(ntsc, frames, 30000, 1001);
  EXPECT_EQ(probe(ntsc).at("r_frame_rate"), "30000/1001");
  auto reader = open(ntsc);
  EXPECT_EQ(reader->info().fps_num, 30000);
  EXPECT_EQ(reader->info().fps_den, 1001);
  EXPECT_EQ(read_all(*reader).size(), 30u);
  fs::remove_all(dir);
}

TEST(Video, NoFramesIsAnEmptyVideo) {
  const auto dir = temp_dir();
  const auto file = dir / "empty.mkv";
  hydrolux::io::OutputFile out(file);
  VideoInfo info;
  info.width = 32;
  info.height = 32;
  info.fps_num = 25;
  auto writer = video_api().open_writer(
      [&out](std::uint64_t offset, std::string_view bytes) { out.write_at(offset, bytes); }, ".mkv", info, 18, "x");
  writer->finish();
  writer.reset();
  out.commit();
  try {
    auto reader = open(file);
    VideoFrame f;
    EXPECT_FALSE(reader->read(f));
  } catch (const IoError& e) {
    // A container whose only stream never had a packet may not state its codec's parameters:
    // refused at open, with a message, is fine too.
    expect_one_line_naming(e.what(), file.string());
  }
  fs::remove_all(dir);
}

// A stream whose frames change size midway (two H.264 elementary streams, 96x64 then 64x48, one after
// the other in an MPEG-TS file): the reader refuses the first frame of the other size, naming both
// sizes, instead of stretching it to the first (issue 37: "frame 40/20", stretched frames).
TEST(Video, RefusesFramesThatChangeSize) {
  const auto dir = temp_dir();
  const auto a = dir / "a.ts", b = dir / "b.ts", both = dir / "both.ts";
  ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=25 -frames:v 6 -pix_fmt yuv420p -c:v libx264 '" + a.string() + "'");
  ffmpeg("-f lavfi -i testsrc2=size=64x48:rate=25 -frames:v 6 -pix_fmt yuv420p -c:v libx264 '" + b.string() + "'");
  {
    std::ofstream out(both, std::ios::binary);
    out << hydrolux::testing::slurp(a) << hydrolux::testing::slurp(b);
  }
  auto reader = open(both);
  ASSERT_EQ(reader->info().width, 96);
  std::vector<VideoFrame> frames;
  VideoFrame f;
  expect_io_error(
      [&] {
        while (reader->read(f)) frames.push_back(f);
      },
      both.string(), "64 x 48");
  EXPECT_EQ(frames.size(), 6u);  // the first size's frames, each unstretched
  for (const auto& g : frames) EXPECT_EQ(g.width, 96);
  fs::remove_all(dir);
}

TEST(Video, RefusesWhatIsNotAVideo) {
  const auto dir = temp_dir();
  const auto good = dir / "good.mp4";
  ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=25 -frames:v 10 -pix_fmt yuv420p -c:v libx264 '" + good.string() + "'");
  const std::string bytes = hydrolux::testing::slurp(good);
  ASSERT_GT(bytes.size(), 1000u);

  std::mt19937 rng(7);
  std::string garbage(4096, '\0');
  for (auto& c : garbage) c = char(rng());
  const std::pair<const char*, std::string> files[] = {
      {"garbage.mp4", garbage},
      {"empty.mp4", ""},
      {"truncated.mp4", bytes.substr(0, bytes.size() / 2)},
      {"text.mkv", "this is not a video\n"},
  };
  for (const auto& [name, content] : files) {
    SCOPED_TRACE(name);
    const auto file = dir / name;
    std::ofstream(file, std::ios::binary) << content;
    expect_io_error([&] { read_all(*open(file)); }, file.string());
  }

  // A PNG is a one-frame "video" to libavformat, and an audio file has no video stream.
  const auto png = dir / "still.png", wav = dir / "tone.wav";
  ffmpeg("-f lavfi -i color=c=red:size=16x16 -frames:v 1 '" + png.string() + "'");
  ffmpeg("-f lavfi -i sine=frequency=440:duration=0.2 '" + wav.string() + "'");
  expect_io_error([&] { open(png); }, png.string(), "still image");
  expect_io_error([&] { open(wav); }, wav.string(), "no video stream");

  // Frames beyond the limits are refused before any is decoded.
  VideoLimits small;
  small.max_side = 64;
  expect_io_error([&] { open(good, small); }, good.string(), "limit is 64 pixels a side");
  small = {};
  small.max_pixels = 96 * 64 - 1;
  expect_io_error([&] { open(good, small); }, good.string(), "limit is 6143 pixels");

  // The caller's read error comes back as it was thrown.
  const auto failing = [](std::uint64_t offset, char*, std::size_t) -> std::size_t {
    throw IoFailure("in.mp4: read failed at " + std::to_string(offset));
  };
  EXPECT_THROW(video_api().open_reader(failing, 1000, "in.mp4", {}), IoFailure);
  // ... also midway through the frames: raw video in Matroska, 1.8 MB, more than the reader's
  // buffer holds, so frames are read after open_reader has returned.
  const auto raw = dir / "raw.mkv";
  ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=25 -frames:v 200 -pix_fmt yuv420p -c:v rawvideo '" + raw.string() + "'");
  hydrolux::io::InputFile in(raw);
  bool broken = false;
  auto reader = video_api().open_reader(
      [&](std::uint64_t offset, char* buffer, std::size_t size) -> std::size_t {
        if (broken) throw IoFailure("raw.mkv: read failed: Input/output error");
        return in.read_at(offset, buffer, size);
      },
      in.size(), "raw.mkv", {});
  VideoFrame f;
  ASSERT_TRUE(reader->read(f));
  broken = true;
  EXPECT_THROW(
      {
        while (reader->read(f)) {
        }
      },
      IoFailure);
  EXPECT_THROW(reader->read(f), IoError);  // and refuses to go on
  fs::remove_all(dir);
}

TEST(Video, WriterRefusesBadSettingsAndKeepsTheCallersErrors) {
  int writes = 0;
  const auto sink = [&writes](std::uint64_t, std::string_view) { ++writes; };
  VideoInfo info;
  info.width = 97;
  info.height = 64;
  info.fps_num = 25;
  expect_io_error([&] { video_api().open_writer(sink, ".mp4", info, 18, "-o odd.mp4"); }, "-o odd.mp4", "even");
  info.width = 96;
  expect_io_error([&] { video_api().open_writer(sink, ".avi", info, 18, "-o x.avi"); }, "-o x.avi", ".mp4");
  expect_io_error([&] { video_api().open_writer(sink, ".mp4", info, 99, "-o x.mp4"); }, "-o x.mp4", "CRF");
  info.fps_num = 0;
  expect_io_error([&] { video_api().open_writer(sink, ".mp4", info, 18, "-o x.mp4"); }, "-o x.mp4", "frame rate");
  info.fps_num = 25;
  info.width = 1 << 15;
  expect_io_error([&] { video_api().open_writer(sink, ".mp4", info, 18, "-o x.mp4"); }, "-o x.mp4", "limit");
  info.width = 96;
  EXPECT_EQ(writes, 0);

  // A frame of the wrong size is the caller's bug: Error, and the writer stops.
  auto writer = video_api().open_writer(sink, ".mkv", info, 18, "-o x.mkv");
  EXPECT_THROW(writer->write(gradient(32, 32, 0)), Error);
  EXPECT_THROW(writer->write(gradient(96, 64, 0)), Error);

  // A full disk midway: the caller's IoFailure comes back unchanged, from write() or finish().
  std::uint64_t written = 0;
  auto full = video_api().open_writer(
      [&written](std::uint64_t, std::string_view bytes) {
        if (written + bytes.size() > 3000) throw IoFailure("-o x.mp4: No space left on device");
        written += bytes.size();
      },
      ".mp4", info, 18, "-o x.mp4");
  EXPECT_THROW(
      {
        for (int k = 0; k < 60; ++k) full->write(gradient(96, 64, k));
        full->finish();
      },
      IoFailure);

  // Abandoned without finish(): freed without writing or throwing.
  writes = 0;
  {
    auto abandoned = video_api().open_writer(sink, ".mp4", info, 18, "-o x.mp4");
    for (int k = 0; k < 5; ++k) abandoned->write(gradient(96, 64, k));
    const int before = writes;
    abandoned.reset();
    EXPECT_EQ(writes, before);
  }
}

}  // namespace
