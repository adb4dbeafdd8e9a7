#pragma once
// Video files (`hydrolux rain --video`, hydrolux._video), through FFmpeg's libraries (libavformat,
// libavcodec, libswscale, libavutil from Debian). The implementation (src/io/video_ffmpeg.cpp, the
// object library hydrolux_video) is reached two ways: the CLI loads it on first use from the plugin
// libhydrolux_video_plugin.so beside its executable (video_api() below), as it does its image plugin,
// so that only the commands that touch video pay for loading FFmpeg; the Python module and the fuzz
// target link it directly and call hydrolux_video_api_v1().
//
// The implementation never opens a file. The caller reads and writes the bytes through
// io/files.hpp (io::InputFile, io::OutputFile::write_at), so an input is checked as every input is,
// an output appears whole or not at all, and the CLI's Ctrl-C handler removes a pending output; the
// implementation sees only the two callbacks below.
//
// Frames are 8-bit RGB, interleaved, row 0 at the top, taken as sRGB-encoded: the decoder converts
// whatever the stream holds (YUV 4:2:0, 10-bit, ...) to RGB24 with the stream's colour matrix, range
// and chroma siting (an untagged stream is taken as BT.709 from 1280 wide or 577 high, BT.601
// below, as players do), the encoder converts back to YUV 4:2:0 (BT.709 matrix, limited range,
// tagged as such).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace hydrolux::io {

struct VideoInfo {
  int width = 0, height = 0;
  int fps_num = 0, fps_den = 1;    // the video stream's frame rate (average, as a fraction)
  std::int64_t frame_count = -1;   // as the container states it; -1 when it does not
  double duration_s = 0;           // 0 when unknown
  std::string codec;               // the decoder's name ("h264")
  double fps() const { return fps_den > 0 ? double(fps_num) / fps_den : 0; }
};

struct VideoFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;   // width * height * 3
};

// Reads up to `size` bytes at `offset`; returns how many (0 at the end). Throws on a read error.
using ReadAt = std::function<std::size_t(std::uint64_t offset, char* buffer, std::size_t size)>;
// Writes `bytes` at `offset` of the output. Throws on a write error.
using WriteAt = std::function<void(std::uint64_t offset, std::string_view bytes)>;

class VideoReader {
 public:
  virtual ~VideoReader() = default;
  virtual const VideoInfo& info() const = 0;
  // The next frame in presentation order, every decoded frame once (none dropped or repeated);
  // false after the last. IoError naming the origin for a stream that cannot be decoded (a corrupt
  // packet is an error, not concealed); after any exception the reader refuses to go on. A
  // container cut short where its format allows it (Matroska, MPEG-TS) gives the frames it holds.
  // The caller's exception from ReadAt comes back unchanged.
  virtual bool read(VideoFrame& frame) = 0;
};

class VideoWriter {
 public:
  virtual ~VideoWriter() = default;
  // Appends one frame (info.width x info.height), shown for 1 / fps. A frame of another size is
  // hydrolux::Error. The caller's exception from WriteAt comes back unchanged; after any exception
  // the writer refuses to go on.
  virtual void write(const VideoFrame& frame) = 0;
  // Flushes the encoder and writes the container's trailer. Nothing is complete before this. The
  // destructor of an unfinished writer frees everything and writes nothing more.
  virtual void finish() = 0;
};

struct VideoLimits {
  int max_side = 16384;                          // width or height, pixels
  std::int64_t max_pixels = std::int64_t(1) << 26;  // width x height of one frame (8K is 2^25)
};

struct VideoApi {
  // Opens the first video stream of a container (MP4, MOV, MKV, WebM, AVI, ...: what Debian's
  // libavformat reads). `origin` names the input in errors. IoError (one line) for bytes that are
  // not a video container, no video stream, a codec with no decoder, or a frame size beyond limits.
  std::unique_ptr<VideoReader> (*open_reader)(ReadAt read, std::uint64_t size, std::string origin,
                                              const VideoLimits& limits);
  // Starts a video with `info`'s size and frame rate in the container that `extension` names
  // (".mp4", ".mov", ".mkv"), encoded H.264 (libx264, CRF `crf`, preset medium, yuv420p; odd sizes
  // are refused with IoError as H.264 4:2:0 needs even ones; so are a CRF outside [0, 51], a rate
  // outside (0, 1000] frames per second and sizes beyond VideoLimits' defaults). Video only: audio is
  // not carried. The output is written only through `write`. The same frames give the same bytes on
  // machines with the same CPU features (a fixed count of x264 threads; no random IDs).
  std::unique_ptr<VideoWriter> (*open_writer)(WriteAt write, std::string extension, const VideoInfo& info,
                                              int crf, std::string origin);
};

// The plugin's entry point, `extern "C"` so that its name is not mangled (hydrolux_video_api_v1
// below).
inline constexpr const char* kVideoPluginSymbol = "hydrolux_video_api_v1";
inline constexpr const char* kVideoPluginFile = "libhydrolux_video_plugin.so";

// Loads the plugin (once; thread-safe) from the directory of the running executable (io/plugin.hpp).
// Throws hydrolux::Error naming the file and the loader's reason if it cannot.
const VideoApi& video_api();

// The container extensions open_writer accepts, lower case with the dot.
inline constexpr std::string_view kVideoExtensions[] = {".mp4", ".mov", ".mkv"};

}  // namespace hydrolux::io

// The implementation itself, for code that links the object library hydrolux_video instead of
// loading the plugin.
extern "C" const hydrolux::io::VideoApi* hydrolux_video_api_v1();
