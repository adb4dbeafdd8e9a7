// libFuzzer target: video through hydrolux/io/video.hpp's FFmpeg code (src/io/video_ffmpeg.cpp,
// the object library hydrolux_video, linked in directly): FFmpeg's demuxers reading the bytes
// through its AVIOContext (reads and seeks anywhere, the size asked for), stream selection, the
// decoder and the conversion to RGB.
// Small limits and at most a few frames keep a run fast. Invariants: a refused input throws
// hydrolux::Error, nothing else; an accepted one has a frame size within the limits, and every
// frame is exactly that size.
//
// FFmpeg itself is Debian's uninstrumented build: the fuzzer's coverage sees only hydrolux's code,
// so this is a robustness check of its handling of FFmpeg's answers (and of FFmpeg under
// AddressSanitizer's allocator) rather than a coverage-guided search inside FFmpeg.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/video.hpp"

namespace {
void check(bool ok) {
  if (!ok) std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hydrolux;
  const auto read = [data, size](std::uint64_t offset, char* buffer, std::size_t n) -> std::size_t {
    check(buffer != nullptr);
    if (offset >= size) return 0;
    const std::size_t k = std::min<std::uint64_t>(n, size - offset);
    std::memcpy(buffer, data + offset, k);
    return k;
  };
  io::VideoLimits limits;
  limits.max_side = 512;
  limits.max_pixels = std::int64_t(1) << 18;
  try {
    const auto reader = hydrolux_video_api_v1()->open_reader(read, size, "fuzz", limits);
    const io::VideoInfo& info = reader->info();
    check(info.width > 0 && info.height > 0 && info.width <= limits.max_side && info.height <= limits.max_side &&
          std::int64_t(info.width) * info.height <= limits.max_pixels);
    check(info.fps_den > 0 && info.fps_num >= 0 && info.duration_s >= 0);
    io::VideoFrame frame;
    for (int i = 0; i < 4 && reader->read(frame); ++i)
      check(frame.width == info.width && frame.height == info.height &&
            frame.rgb.size() == std::size_t(info.width) * std::size_t(info.height) * 3);
  } catch (const Error&) {
    // IoError: refused with a message. Anything else (bad_alloc, a crash) is a finding.
  }
  return 0;
}
