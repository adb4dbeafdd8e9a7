// Video files through FFmpeg (see hydrolux/io/video.hpp): FFmpeg's demuxers and decoders, libx264
// and the muxers, and libswscale's colour conversion behind one symbol, hydrolux_video_api_v1. Built
// as the object library hydrolux_video: the CLI's plugin libhydrolux_video_plugin.so, the Python
// module hydrolux._video and fuzz/fuzz_video link it. FFmpeg's types stay in this file.
//
// Bytes move only through the caller's ReadAt / WriteAt, wrapped in custom AVIOContexts. FFmpeg is
// C: an exception thrown by a callback must not unwind through it, so the callbacks catch it, hand
// FFmpeg an I/O error, and the exception is rethrown unchanged once FFmpeg has returned (an
// IoFailure for a full disk stays an IoFailure).
//
// FFmpeg prints its diagnostics to stderr; hydrolux's contract is one line per error. This code
// installs a log callback that prints nothing and keeps the last error-level line logged on the
// calling thread, which then becomes the detail of our IoError ("moov atom not found").
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavformat/avio.h>
#include <libavutil/avutil.h>
#include <libavutil/cpu.h>
#include <libavutil/dict.h>
#include <libavutil/frame.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/mathematics.h>
#include <libavutil/opt.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <exception>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/video.hpp"

namespace {

using hydrolux::Error;
using hydrolux::IoError;
using hydrolux::io::ReadAt;
using hydrolux::io::VideoFrame;
using hydrolux::io::VideoInfo;
using hydrolux::io::VideoLimits;
using hydrolux::io::WriteAt;

// An AVIOContext seek over bytes of which `size` exist (the input's size, or the end written so
// far): AVSEEK_SIZE answers the size; SEEK_SET / CUR / END move `position` (AVERROR(EINVAL) for a
// position before 0 or past INT64_MAX).
std::int64_t avio_seek_position(std::uint64_t& position, std::uint64_t size, std::int64_t offset, int whence) {
  whence &= ~AVSEEK_FORCE;
  if (whence == AVSEEK_SIZE) return std::int64_t(size);
  std::int64_t base;
  switch (whence) {
    case SEEK_SET: base = 0; break;
    case SEEK_CUR: base = std::int64_t(position); break;
    case SEEK_END: base = std::int64_t(size); break;
    default: return AVERROR(EINVAL);
  }
  if ((offset > 0 && base > INT64_MAX - offset) || base + offset < 0) return AVERROR(EINVAL);
  position = std::uint64_t(base + offset);
  return base + offset;
}

// x264's frame threads change the bitstream with their number, so the count is fixed here rather
// than taken from the machine's cores: the same frames then give the same bytes on every machine
// with the same CPU features (x264's SIMD paths differ in their last bits, so a CPU without AVX2
// gives other, equally valid, bytes). Eight keeps a 16-core machine mostly busy at 1080p and costs
// little on two cores.
constexpr int kEncoderThreads = 8;

// x264 164 (Debian 12) with its AVX-512 routines and MB-tree on (preset medium) encodes the same
// frames to different bytes from one encoder to the next in a process, at many small widths (96,
// 192, 304 pixels; not 320 or 1280): something there reads memory it did not write. Without
// AVX-512 (the AVX2 set, which x264 picks itself on CPUs without AVX-512, and which every AVX-512
// CPU has) the output is repeatable. Found by tests/cli/test_video.cpp on an AMD EPYC.
constexpr const char* kX264WithoutAvx512 = "asm=AVX2";
constexpr int kIoBufferBytes = 1 << 18;  // the AVIOContexts' buffers

// ---- FFmpeg's messages --------------------------------------------------------------------------

thread_local std::string t_log_partial;  // an error line logged in pieces, until its newline
thread_local std::string t_log_last;     // the last complete error line on this thread

void log_callback(void*, int level, const char* format, va_list args) {
  if (level > AV_LOG_ERROR) return;  // warnings and chatter: nothing
  char buffer[1024];
  const int n = std::vsnprintf(buffer, sizeof buffer, format, args);
  if (n <= 0) return;
  if (t_log_partial.size() < 4096) t_log_partial += buffer;
  if (!t_log_partial.empty() && t_log_partial.back() == '\n') {
    t_log_last = std::move(t_log_partial);
    t_log_partial.clear();
  }
}

void quiet_ffmpeg() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_callback(&log_callback); });
  t_log_partial.clear();
  t_log_last.clear();
}

// One line of at most 200 characters: control characters become spaces, the ends are trimmed.
std::string one_line(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  const auto first = text.find_first_not_of(' ');
  if (first == std::string::npos) return {};
  text = text.substr(first, text.find_last_not_of(' ') - first + 1);
  if (text.size() > 200) text = text.substr(0, 197) + "...";
  return text;
}

std::string error_text(int code) {
  char buffer[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, buffer, sizeof buffer);
  return one_line(buffer);
}

// What failed and why: FFmpeg's logged line if it wrote one, with the error code's text.
std::string reason(int code) {
  std::string logged = one_line(t_log_last);
  t_log_last.clear();
  const std::string coded = error_text(code);
  if (logged.empty() || logged == coded) return coded;
  return fmt::format("{} ({})", logged, coded);
}

// ---- owners of FFmpeg objects ---------------------------------------------------------------------

struct CodecFree {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameFree {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketFree {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct SwsFree {
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};
// A custom AVIOContext's buffer may have been replaced by FFmpeg, so free the one it holds now.
struct AvioFree {
  void operator()(AVIOContext* io) const {
    av_freep(&io->buffer);
    avio_context_free(&io);
  }
};
struct DictFree {
  void operator()(AVDictionary* d) const { av_dict_free(&d); }
};
using CodecPtr = std::unique_ptr<AVCodecContext, CodecFree>;
using FramePtr = std::unique_ptr<AVFrame, FrameFree>;
using PacketPtr = std::unique_ptr<AVPacket, PacketFree>;
using SwsPtr = std::unique_ptr<SwsContext, SwsFree>;
using AvioPtr = std::unique_ptr<AVIOContext, AvioFree>;

FramePtr new_frame() {
  FramePtr f(av_frame_alloc());
  if (!f) throw std::bad_alloc();
  return f;
}

PacketPtr new_packet() {
  PacketPtr p(av_packet_alloc());
  if (!p) throw std::bad_alloc();
  return p;
}

AvioPtr new_avio(void* opaque, bool write, int (*read_packet)(void*, std::uint8_t*, int),
                 int (*write_packet)(void*, std::uint8_t*, int), std::int64_t (*seek)(void*, std::int64_t, int)) {
  auto* buffer = static_cast<std::uint8_t*>(av_malloc(kIoBufferBytes));
  if (!buffer) throw std::bad_alloc();
  AVIOContext* io = avio_alloc_context(buffer, kIoBufferBytes, write ? 1 : 0, opaque, read_packet, write_packet, seek);
  if (!io) {
    av_free(buffer);
    throw std::bad_alloc();
  }
  return AvioPtr(io);
}

// A frame of `format` at `width` x `height` with FFmpeg's alignment and padding (libswscale's SIMD
// may read or write a little past a row's end, which a std::vector of exactly w * h * 3 would not
// allow).
FramePtr new_image(AVPixelFormat format, int width, int height) {
  FramePtr f = new_frame();
  f->format = format;
  f->width = width;
  f->height = height;
  if (av_frame_get_buffer(f.get(), 0) < 0) throw std::bad_alloc();
  // Zeroed, padding included: what an encoder's SIMD reads past a row's end is then always the same.
  for (AVBufferRef* b : f->buf)
    if (b) std::memset(b->data, 0, b->size);
  return f;
}

// Sets a libswscale option that must exist (a misspelt name would silently change the conversion).
void sws_option(SwsContext* s, const char* name, std::int64_t value) {
  if (av_opt_set_int(s, name, value, 0) < 0) throw Error(fmt::format("libswscale has no option '{}'", name));
}

// swscale's position of chroma samples (1/256 of a luma sample), from the stream's siting; H.264's
// and HEVC's default, left (co-sited horizontally, between the rows vertically), when unstated.
std::pair<int, int> chroma_position(AVChromaLocation location) {
  int x = 0, y = 128;
  if (location == AVCHROMA_LOC_UNSPECIFIED || avcodec_enum_to_chroma_pos(&x, &y, location) < 0) return {0, 128};
  return {x, y};
}

// ---- reading ------------------------------------------------------------------------------------

// Demuxers that read one still picture (FFmpeg's image2 family: png_pipe, jpeg_pipe, ...): a PNG is
// a one-frame "video" to libavformat, not a video to a user.
bool still_image_demuxer(std::string_view name) {
  return name == "image2" || name == "image2pipe" || (name.size() > 5 && name.substr(name.size() - 5) == "_pipe");
}

// The YUV -> RGB matrix of a stream (libswscale's SWS_CS_*). Untagged streams get what players
// assume (mpv, for one): BT.709 for HD sizes, BT.601 below.
int yuv_matrix(AVColorSpace space, int width, int height) {
  switch (space) {
    case AVCOL_SPC_BT709: return SWS_CS_ITU709;
    case AVCOL_SPC_FCC: return SWS_CS_FCC;
    case AVCOL_SPC_BT470BG:
    case AVCOL_SPC_SMPTE170M: return SWS_CS_ITU601;
    case AVCOL_SPC_SMPTE240M: return SWS_CS_SMPTE240M;
    case AVCOL_SPC_BT2020_NCL:
    case AVCOL_SPC_BT2020_CL: return SWS_CS_BT2020;  // constant luminance approximated as NCL
    default: return width >= 1280 || height > 576 ? SWS_CS_ITU709 : SWS_CS_ITU601;
  }
}

bool full_range(AVPixelFormat format, AVColorRange range) {
  // The deprecated yuvj formats are full range whatever the tag says.
  return range == AVCOL_RANGE_JPEG || format == AV_PIX_FMT_YUVJ420P || format == AV_PIX_FMT_YUVJ422P ||
         format == AV_PIX_FMT_YUVJ444P || format == AV_PIX_FMT_YUVJ440P || format == AV_PIX_FMT_YUVJ411P;
}

// The demuxer, format and codec contexts are freed in reverse order of members: the format context
// before the AVIOContext it reads through.
class Reader final : public hydrolux::io::VideoReader {
 public:
  Reader(ReadAt read, std::uint64_t size, std::string origin, const VideoLimits& limits)
      : read_(std::move(read)), size_(size), origin_(std::move(origin)), limits_(limits) {
    quiet_ffmpeg();
    if (limits_.max_side <= 0 || limits_.max_pixels <= 0)
      throw Error(fmt::format("{}: the video limits are not positive", origin_));
    io_ = new_avio(this, false, &Reader::read_packet, nullptr, &Reader::seek);
    open_container();
    open_decoder();
    frame_ = new_frame();
    packet_ = new_packet();
  }

  ~Reader() override = default;

  const VideoInfo& info() const override { return info_; }

  bool read(VideoFrame& out) override {
    if (failed_) throw IoError(fail("the video could not be read further after an earlier error"));
    if (done_) return false;
    try {
      t_log_last.clear();
      if (!next_frame()) {
        done_ = true;
        return false;
      }
      convert(out);
      av_frame_unref(frame_.get());
      ++decoded_;
      return true;
    } catch (...) {
      failed_ = true;
      throw;
    }
  }

 private:
  struct FormatClose {
    void operator()(AVFormatContext* f) const { avformat_close_input(&f); }
  };

  IoError fail(const std::string& why) const { return IoError(fmt::format("{}: {}", origin_, why)); }

  // The caller's exception from a callback, if one was thrown during the last FFmpeg call.
  void rethrow_pending() {
    if (pending_) std::rethrow_exception(std::exchange(pending_, nullptr));
  }

  static int read_packet(void* opaque, std::uint8_t* buffer, int size) {
    auto* self = static_cast<Reader*>(opaque);
    if (self->pending_) return AVERROR(EIO);
    if (self->position_ >= self->size_ || size <= 0) return AVERROR_EOF;
    const auto want = std::size_t(std::min<std::uint64_t>(std::uint64_t(size), self->size_ - self->position_));
    std::size_t got = 0;
    try {
      got = std::min(want, self->read_(self->position_, reinterpret_cast<char*>(buffer), want));
    } catch (...) {
      self->pending_ = std::current_exception();
      return AVERROR(EIO);
    }
    if (got == 0) return AVERROR_EOF;  // the input shrank under us: its end is here
    self->position_ += got;
    return int(got);
  }

  static std::int64_t seek(void* opaque, std::int64_t offset, int whence) {
    auto* self = static_cast<Reader*>(opaque);
    return avio_seek_position(self->position_, self->size_, offset, whence);
  }

  // Nested files (HLS playlists, DASH manifests, MOV references, concat lists) are refused: the
  // input is the caller's bytes and nothing else.
  static int refuse_open(AVFormatContext*, AVIOContext**, const char*, int, AVDictionary**) { return AVERROR(EPERM); }

  void open_container() {
    AVFormatContext* raw = avformat_alloc_context();
    if (!raw) throw std::bad_alloc();
    raw->pb = io_.get();
    raw->flags |= AVFMT_FLAG_CUSTOM_IO;
    raw->io_open = &Reader::refuse_open;
    // No file name: the container is recognised from its bytes alone, never from an extension.
    int r = avformat_open_input(&raw, "", nullptr, nullptr);  // frees `raw` on failure
    rethrow_pending();
    if (r < 0) throw fail(fmt::format("not a video file FFmpeg reads: {}", reason(r)));
    format_.reset(raw);
    const std::string_view demuxer = format_->iformat->name;
    if (still_image_demuxer(demuxer)) {
      std::string kind(demuxer.substr(0, demuxer.find('_')));  // "png_pipe" -> PNG
      for (char& c : kind) c = char(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
      throw fail(fmt::format("a still image ({}), not a video", kind));
    }

    // find_stream_info decodes a few frames of each stream: the pixel limit holds there too.
    const unsigned streams = format_->nb_streams;
    std::vector<AVDictionary*> options(streams, nullptr);
    for (auto& o : options) av_dict_set_int(&o, "max_pixels", limits_.max_pixels, 0);
    r = avformat_find_stream_info(format_.get(), streams ? options.data() : nullptr);
    for (auto& o : options) av_dict_free(&o);
    rethrow_pending();
    if (r < 0) throw fail(fmt::format("cannot read the {} container: {}", demuxer, reason(r)));

    const AVCodec* decoder = nullptr;
    int index = av_find_best_stream(format_.get(), AVMEDIA_TYPE_VIDEO, -1, -1, &decoder, 0);
    if (index >= 0 && (format_->streams[index]->disposition & AV_DISPOSITION_ATTACHED_PIC)) {
      index = AVERROR_STREAM_NOT_FOUND;  // cover art: look for a moving picture
      for (unsigned i = 0; i < format_->nb_streams; ++i) {
        const AVStream* s = format_->streams[i];
        if (s->codecpar->codec_type == AVMEDIA_TYPE_VIDEO && !(s->disposition & AV_DISPOSITION_ATTACHED_PIC)) {
          index = int(i);
          decoder = avcodec_find_decoder(s->codecpar->codec_id);
          break;
        }
      }
    }
    if (index < 0 && index != AVERROR_DECODER_NOT_FOUND)
      throw fail(fmt::format("no video stream in the {} container", demuxer));
    if (index == AVERROR_DECODER_NOT_FOUND || !decoder) {
      // av_find_best_stream reports the missing decoder without the stream: name the codec of the
      // first video stream.
      for (unsigned i = 0; i < format_->nb_streams; ++i)
        if (format_->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO)
          throw fail(fmt::format("no decoder for its video codec '{}'",
                                 avcodec_get_name(format_->streams[i]->codecpar->codec_id)));
      throw fail("no decoder for its video codec");
    }
    stream_ = format_->streams[index];
    decoder_ = decoder;
    for (unsigned i = 0; i < format_->nb_streams; ++i)
      if (int(i) != index) format_->streams[i]->discard = AVDISCARD_ALL;

    const AVCodecParameters* par = stream_->codecpar;
    const std::int64_t w = par->width, h = par->height;
    if (w <= 0 || h <= 0) throw fail(fmt::format("the video stream has no frame size ({} x {})", w, h));
    check_size(w, h);
    info_.width = int(w);
    info_.height = int(h);
    AVRational rate = stream_->avg_frame_rate;
    if (rate.num <= 0 || rate.den <= 0) rate = stream_->r_frame_rate;
    if (rate.num > 0 && rate.den > 0) {
      av_reduce(&info_.fps_num, &info_.fps_den, rate.num, rate.den, INT32_MAX);
    } else {
      info_.fps_num = 0;
      info_.fps_den = 1;
    }
    info_.frame_count = stream_->nb_frames > 0 ? stream_->nb_frames : -1;
    double duration = 0;
    if (stream_->duration > 0 && stream_->time_base.num > 0 && stream_->time_base.den > 0)
      duration = double(stream_->duration) * av_q2d(stream_->time_base);
    else if (format_->duration > 0)
      duration = double(format_->duration) / AV_TIME_BASE;
    info_.duration_s = std::isfinite(duration) && duration > 0 ? duration : 0;
    info_.codec = decoder_->name;
  }

  void check_size(std::int64_t w, std::int64_t h) const {
    if (w > limits_.max_side || h > limits_.max_side)
      throw fail(fmt::format("frames of {} x {} pixels; the limit is {} pixels a side", w, h, limits_.max_side));
    if (w * h > limits_.max_pixels)
      throw fail(fmt::format("frames of {} x {} pixels; the limit is {} pixels", w, h, limits_.max_pixels));
  }

  void open_decoder() {
    codec_.reset(avcodec_alloc_context3(decoder_));
    if (!codec_) throw std::bad_alloc();
    int r = avcodec_parameters_to_context(codec_.get(), stream_->codecpar);
    if (r < 0) throw fail(fmt::format("cannot set up the {} decoder: {}", decoder_->name, reason(r)));
    codec_->pkt_timebase = stream_->time_base;
    codec_->max_pixels = limits_.max_pixels;
    codec_->thread_count = 0;  // as many as the machine has (FFmpeg's decoders are exact with any count)
    codec_->thread_type = FF_THREAD_FRAME | FF_THREAD_SLICE;
    r = avcodec_open2(codec_.get(), decoder_, nullptr);
    if (r < 0) throw fail(fmt::format("cannot open the {} decoder: {}", decoder_->name, reason(r)));
  }

  // Decodes into frame_; false after the last frame.
  bool next_frame() {
    for (;;) {
      int r = avcodec_receive_frame(codec_.get(), frame_.get());
      if (r == 0) return true;
      if (r == AVERROR_EOF) return false;
      if (r != AVERROR(EAGAIN)) throw decode_error(r);
      if (flushing_) throw fail("the decoder stalled while flushing");
      r = av_read_frame(format_.get(), packet_.get());
      rethrow_pending();
      if (r == AVERROR_EOF) {
        flushing_ = true;  // the end: a null packet makes the decoder give up the frames it holds
        r = avcodec_send_packet(codec_.get(), nullptr);
        if (r < 0 && r != AVERROR_EOF) throw decode_error(r);
        continue;
      }
      if (r < 0) throw fail(fmt::format("cannot read the {} container after frame {}: {}", format_->iformat->name,
                                        decoded_, reason(r)));
      if (packet_->stream_index != stream_->index) {
        av_packet_unref(packet_.get());
        continue;
      }
      r = avcodec_send_packet(codec_.get(), packet_.get());
      av_packet_unref(packet_.get());
      if (r < 0 && r != AVERROR(EAGAIN)) throw decode_error(r);
    }
  }

  IoError decode_error(int code) const {
    return fail(fmt::format("cannot decode the {} video after frame {}: {}", decoder_->name, decoded_, reason(code)));
  }

  // frame_ -> 8-bit RGB at the stream's size, with the frame's own matrix, range and chroma siting.
  void convert(VideoFrame& out) {
    const AVFrame* f = frame_.get();
    const auto format = static_cast<AVPixelFormat>(f->format);
    if (f->width <= 0 || f->height <= 0) throw fail(fmt::format("frame {} is empty", decoded_));
    check_size(f->width, f->height);
    // A stream whose frames change size midway: they are not stretched to the first size (a folder
    // refuses such a frame too).
    if (f->width != info_.width || f->height != info_.height)
      throw fail(fmt::format("frame {} is {} x {} pixels, the video's frames {} x {}: frames that change size are "
                             "not supported (split the video where the size changes)",
                             decoded_ + 1, f->width, f->height, info_.width, info_.height));
    if (!sws_isSupportedInput(format))
      throw fail(fmt::format("pixel format {} cannot be converted to RGB", av_get_pix_fmt_name(format)
                                                                              ? av_get_pix_fmt_name(format)
                                                                              : "?"));
    // The frame's own tags, else the stream's; a hostile file can make a decoder store a value outside
    // the enum (chroma location 33 was seen by fuzz_video), which is read as its integer and taken as
    // unspecified.
    const auto frame_or_stream = [](const auto& from_frame, const auto& from_stream, auto unspecified, auto count) {
      const auto tag = [&](const auto& field) {
        using E = std::decay_t<decltype(field)>;
        std::underlying_type_t<E> raw;
        std::memcpy(&raw, &field, sizeof raw);
        const long long v = static_cast<long long>(raw);
        return v >= 0 && v < static_cast<long long>(count) ? static_cast<E>(raw) : unspecified;
      };
      const auto own = tag(from_frame);
      return own != unspecified ? own : tag(from_stream);
    };
    const AVColorSpace space =
        frame_or_stream(f->colorspace, stream_->codecpar->color_space, AVCOL_SPC_UNSPECIFIED, AVCOL_SPC_NB);
    const AVColorRange range =
        frame_or_stream(f->color_range, stream_->codecpar->color_range, AVCOL_RANGE_UNSPECIFIED, AVCOL_RANGE_NB);
    const AVChromaLocation siting = frame_or_stream(f->chroma_location, stream_->codecpar->chroma_location,
                                                    AVCHROMA_LOC_UNSPECIFIED, AVCHROMA_LOC_NB);
    const Conversion key{f->width, f->height, format, yuv_matrix(space, f->width, f->height), full_range(format, range),
                         siting};
    if (!sws_ || !(key == conversion_)) {
      sws_.reset(sws_alloc_context());
      if (!sws_) throw std::bad_alloc();
      SwsContext* s = sws_.get();
      sws_option(s, "srcw", key.width);
      sws_option(s, "srch", key.height);
      sws_option(s, "src_format", key.format);
      sws_option(s, "dstw", info_.width);
      sws_option(s, "dsth", info_.height);
      sws_option(s, "dst_format", AV_PIX_FMT_RGB24);
      // Exact rounding, chroma interpolated to every pixel, and the same output on every CPU.
      sws_option(s, "sws_flags", SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT | SWS_BITEXACT);
      const auto [cx, cy] = chroma_position(key.siting);
      sws_option(s, "src_h_chr_pos", cx);
      sws_option(s, "src_v_chr_pos", cy);
      if (sws_init_context(s, nullptr, nullptr) < 0)
        throw fail(fmt::format("cannot convert {} frames to RGB", av_get_pix_fmt_name(format)));
      const auto* desc = av_pix_fmt_desc_get(format);
      if (desc && !(desc->flags & AV_PIX_FMT_FLAG_RGB) && desc->nb_components >= 3) {
        const int* matrix = sws_getCoefficients(key.matrix);
        sws_setColorspaceDetails(s, matrix, key.full ? 1 : 0, matrix, 1, 0, 1 << 16, 1 << 16);
      }
      rgb_ = new_image(AV_PIX_FMT_RGB24, info_.width, info_.height);
      conversion_ = key;
    }
    const int rows = sws_scale(sws_.get(), f->data, f->linesize, 0, f->height, rgb_->data, rgb_->linesize);
    if (rows != info_.height) throw fail(fmt::format("frame {} could not be converted to RGB", decoded_));
    out.width = info_.width;
    out.height = info_.height;
    const std::size_t row_bytes = std::size_t(info_.width) * 3;
    out.rgb.resize(row_bytes * std::size_t(info_.height));
    for (int y = 0; y < info_.height; ++y)
      std::memcpy(out.rgb.data() + row_bytes * std::size_t(y), rgb_->data[0] + std::ptrdiff_t(y) * rgb_->linesize[0],
                  row_bytes);
  }

  struct Conversion {
    int width = 0, height = 0;
    AVPixelFormat format = AV_PIX_FMT_NONE;
    int matrix = 0;
    bool full = false;
    AVChromaLocation siting = AVCHROMA_LOC_UNSPECIFIED;
    bool operator==(const Conversion&) const = default;
  };

  ReadAt read_;
  std::uint64_t size_;
  std::string origin_;
  VideoLimits limits_;
  std::uint64_t position_ = 0;
  std::exception_ptr pending_;
  AvioPtr io_;
  std::unique_ptr<AVFormatContext, FormatClose> format_;
  AVStream* stream_ = nullptr;
  const AVCodec* decoder_ = nullptr;
  CodecPtr codec_;
  FramePtr frame_, rgb_;
  PacketPtr packet_;
  SwsPtr sws_;
  Conversion conversion_;
  VideoInfo info_;
  std::int64_t decoded_ = 0;
  bool flushing_ = false, done_ = false, failed_ = false;
};

// ---- writing ------------------------------------------------------------------------------------

const char* muxer_for(std::string extension) {
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c); });
  if (extension == ".mp4") return "mp4";
  if (extension == ".mov") return "mov";
  if (extension == ".mkv") return "matroska";
  return nullptr;
}

class Writer final : public hydrolux::io::VideoWriter {
 public:
  Writer(WriteAt write, const std::string& extension, const VideoInfo& info, int crf, std::string origin)
      : write_(std::move(write)), origin_(std::move(origin)) {
    quiet_ffmpeg();
    const char* muxer = muxer_for(extension);
    if (!muxer)
      throw fail(
          fmt::format("cannot write video as '{}'; the containers are .mp4, .mov and .mkv", one_line(extension)));
    const VideoLimits limits;
    const std::int64_t w = info.width, h = info.height;
    if (w <= 0 || h <= 0) throw fail(fmt::format("a video of {} x {} pixels is empty", w, h));
    if (w % 2 || h % 2)
      throw fail(fmt::format("{} x {} pixels: H.264 with 4:2:0 chroma needs an even width and height", w, h));
    if (w > limits.max_side || h > limits.max_side || w * h > limits.max_pixels)
      throw fail(fmt::format("{} x {} pixels is beyond the limit of {} pixels a side and {} pixels", w, h,
                             limits.max_side, limits.max_pixels));
    if (info.fps_num <= 0 || info.fps_den <= 0 || double(info.fps_num) > 1000.0 * info.fps_den)
      throw fail(fmt::format("a frame rate of {}/{} is outside (0, 1000] frames per second", info.fps_num,
                             info.fps_den));
    if (crf < 0 || crf > 51) throw fail(fmt::format("CRF {} is outside [0, 51]", crf));
    width_ = info.width;
    height_ = info.height;
    AVRational rate{};
    av_reduce(&rate.num, &rate.den, info.fps_num, info.fps_den, INT32_MAX);

    AVFormatContext* raw = nullptr;
    int r = avformat_alloc_output_context2(&raw, nullptr, muxer, nullptr);
    if (r < 0 || !raw) throw fail(fmt::format("cannot set up the {} muxer: {}", muxer, reason(r)));
    format_.reset(raw);
    // No random UIDs or version strings: the same frames give the same bytes.
    format_->flags |= AVFMT_FLAG_BITEXACT;

    const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");
    if (!encoder) encoder = avcodec_find_encoder(AV_CODEC_ID_H264);
    if (!encoder) throw fail("this FFmpeg has no H.264 encoder (Debian's libavcodec has libx264)");
    const bool x264 = std::string_view(encoder->name) == "libx264";
    codec_.reset(avcodec_alloc_context3(encoder));
    if (!codec_) throw std::bad_alloc();
    AVCodecContext* c = codec_.get();
    c->width = width_;
    c->height = height_;
    c->time_base = av_inv_q(rate);  // one tick per frame: pts = frame index
    c->framerate = rate;
    c->sample_aspect_ratio = AVRational{1, 1};
    c->pix_fmt = AV_PIX_FMT_YUV420P;
    c->color_primaries = AVCOL_PRI_BT709;
    c->color_trc = AVCOL_TRC_BT709;
    c->colorspace = AVCOL_SPC_BT709;
    c->color_range = AVCOL_RANGE_MPEG;
    c->chroma_sample_location = AVCHROMA_LOC_LEFT;
    c->thread_count = kEncoderThreads;
    if (format_->oformat->flags & AVFMT_GLOBALHEADER) c->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    AVDictionary* options = nullptr;
    av_dict_set_int(&options, "crf", crf, 0);
    av_dict_set(&options, "preset", "medium", 0);
    if (x264 && (av_get_cpu_flags() & AV_CPU_FLAG_AVX512)) av_dict_set(&options, "x264-params", kX264WithoutAvx512, 0);
    r = avcodec_open2(c, encoder, &options);
    // A fallback encoder may not know x264's options; libx264 must have taken both.
    const bool unused = av_dict_count(options) > 0;
    av_dict_free(&options);
    if (r < 0) throw fail(fmt::format("cannot open the {} encoder: {}", encoder->name, reason(r)));
    if (x264 && unused) throw fail("libx264 did not take the options crf, preset and x264-params");

    stream_ = avformat_new_stream(format_.get(), nullptr);
    if (!stream_) throw std::bad_alloc();
    r = avcodec_parameters_from_context(stream_->codecpar, c);
    if (r < 0) throw fail(fmt::format("cannot set up the video stream: {}", reason(r)));
    stream_->time_base = c->time_base;  // a wish: the muxer picks its own in write_header
    stream_->avg_frame_rate = rate;
    stream_->r_frame_rate = rate;

    io_ = new_avio(this, true, nullptr, &Writer::write_packet, &Writer::seek);
    format_->pb = io_.get();
    format_->flags |= AVFMT_FLAG_CUSTOM_IO;
    r = avformat_write_header(format_.get(), nullptr);
    rethrow_pending();
    if (r < 0) throw fail(fmt::format("cannot start the {} container: {}", muxer, reason(r)));

    // Conversion from RGB: BT.709 matrix, limited range, chroma sited left as tagged above; exact
    // rounding, the same on every CPU.
    sws_.reset(sws_alloc_context());
    if (!sws_) throw std::bad_alloc();
    SwsContext* s = sws_.get();
    sws_option(s, "srcw", width_);
    sws_option(s, "srch", height_);
    sws_option(s, "src_format", AV_PIX_FMT_RGB24);
    sws_option(s, "dstw", width_);
    sws_option(s, "dsth", height_);
    sws_option(s, "dst_format", AV_PIX_FMT_YUV420P);
    sws_option(s, "sws_flags", SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INP | SWS_BITEXACT);
    const auto [cx, cy] = chroma_position(AVCHROMA_LOC_LEFT);
    sws_option(s, "dst_h_chr_pos", cx);
    sws_option(s, "dst_v_chr_pos", cy);
    if (sws_init_context(s, nullptr, nullptr) < 0) throw fail("cannot set up the RGB to YUV conversion");
    const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
    sws_setColorspaceDetails(s, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);
    rgb_ = new_image(AV_PIX_FMT_RGB24, width_, height_);
    yuv_ = new_image(AV_PIX_FMT_YUV420P, width_, height_);
    packet_ = new_packet();
  }

  // Frees everything; never writes (a video not finished is abandoned, and the caller's output
  // with it).
  ~Writer() override = default;

  void write(const VideoFrame& frame) override {
    guarded([&] {
      if (finished_) throw Error(fmt::format("{}: a frame written after the video was finished", origin_));
      if (frame.width != width_ || frame.height != height_ ||
          frame.rgb.size() != std::size_t(width_) * std::size_t(height_) * 3)
        throw Error(fmt::format("{}: a frame of {} x {} pixels ({} bytes) in a video of {} x {}", origin_, frame.width,
                                frame.height, frame.rgb.size(), width_, height_));
      const std::size_t row_bytes = std::size_t(width_) * 3;
      for (int y = 0; y < height_; ++y)
        std::memcpy(rgb_->data[0] + std::ptrdiff_t(y) * rgb_->linesize[0],
                    frame.rgb.data() + row_bytes * std::size_t(y), row_bytes);
      // The encoder may still hold a reference to the last picture: then this gives a new buffer.
      if (av_frame_make_writable(yuv_.get()) < 0) throw std::bad_alloc();
      if (sws_scale(sws_.get(), rgb_->data, rgb_->linesize, 0, height_, yuv_->data, yuv_->linesize) != height_)
        throw fail(fmt::format("frame {} could not be converted to YUV", frames_));
      yuv_->pts = frames_++;
      yuv_->color_primaries = AVCOL_PRI_BT709;
      yuv_->color_trc = AVCOL_TRC_BT709;
      yuv_->colorspace = AVCOL_SPC_BT709;
      yuv_->color_range = AVCOL_RANGE_MPEG;
      yuv_->chroma_location = AVCHROMA_LOC_LEFT;
      encode(yuv_.get());
    });
  }

  void finish() override {
    if (finished_) return;
    guarded([&] {
      encode(nullptr);
      const int r = av_write_trailer(format_.get());
      rethrow_pending();
      if (r < 0) throw fail(fmt::format("cannot finish the video: {}", reason(r)));
      avio_flush(io_.get());
      rethrow_pending();
      if (io_->error < 0) throw fail(fmt::format("cannot finish the video: {}", reason(io_->error)));
      finished_ = true;
    });
  }

 private:
  struct FormatFree {
    void operator()(AVFormatContext* f) const { avformat_free_context(f); }
  };

  IoError fail(const std::string& why) const { return IoError(fmt::format("{}: {}", origin_, why)); }

  void rethrow_pending() {
    if (pending_) std::rethrow_exception(std::exchange(pending_, nullptr));
  }

  // Runs `body`; after any exception the writer refuses further work (FFmpeg's state is unknown).
  template <typename Body>
  void guarded(Body&& body) {
    if (failed_) throw Error(fmt::format("{}: the video writer failed earlier", origin_));
    t_log_last.clear();
    try {
      body();
    } catch (...) {
      failed_ = true;
      throw;
    }
  }

  // Sends one frame (null: the end) and muxes every packet the encoder gives back.
  void encode(const AVFrame* frame) {
    int r = avcodec_send_frame(codec_.get(), frame);
    if (r < 0) throw fail(fmt::format("cannot encode frame {}: {}", frames_ - 1, reason(r)));
    for (;;) {
      r = avcodec_receive_packet(codec_.get(), packet_.get());
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      if (r < 0) throw fail(fmt::format("cannot encode frame {}: {}", frames_ - 1, reason(r)));
      av_packet_rescale_ts(packet_.get(), codec_->time_base, stream_->time_base);
      packet_->stream_index = stream_->index;
      r = av_interleaved_write_frame(format_.get(), packet_.get());  // takes the packet's data
      rethrow_pending();
      if (r < 0) throw fail(fmt::format("cannot write frame {}: {}", frames_ - 1, reason(r)));
    }
  }

  static int write_packet(void* opaque, std::uint8_t* buffer, int size) {
    auto* self = static_cast<Writer*>(opaque);
    if (self->pending_) return AVERROR(EIO);
    if (size <= 0) return 0;
    try {
      self->write_(self->position_, std::string_view(reinterpret_cast<const char*>(buffer), std::size_t(size)));
    } catch (...) {
      self->pending_ = std::current_exception();
      return AVERROR(EIO);
    }
    self->position_ += std::uint64_t(size);
    self->end_ = std::max(self->end_, self->position_);
    return size;
  }

  // The MP4 and Matroska muxers come back to fill in sizes and indexes; AVIOContext flushes its
  // buffer before it seeks, so the position tracked here is where the next bytes go.
  static std::int64_t seek(void* opaque, std::int64_t offset, int whence) {
    auto* self = static_cast<Writer*>(opaque);
    return avio_seek_position(self->position_, self->end_, offset, whence);
  }

  WriteAt write_;
  std::string origin_;
  int width_ = 0, height_ = 0;
  std::uint64_t position_ = 0, end_ = 0;
  std::exception_ptr pending_;
  AvioPtr io_;  // declared before format_, so freed after it
  std::unique_ptr<AVFormatContext, FormatFree> format_;
  AVStream* stream_ = nullptr;
  CodecPtr codec_;
  SwsPtr sws_;
  FramePtr rgb_, yuv_;
  PacketPtr packet_;
  std::int64_t frames_ = 0;
  bool finished_ = false, failed_ = false;
};

std::unique_ptr<hydrolux::io::VideoReader> open_reader(ReadAt read, std::uint64_t size, std::string origin,
                                                        const VideoLimits& limits) {
  return std::make_unique<Reader>(std::move(read), size, std::move(origin), limits);
}

std::unique_ptr<hydrolux::io::VideoWriter> open_writer(WriteAt write, std::string extension, const VideoInfo& info,
                                                        int crf, std::string origin) {
  return std::make_unique<Writer>(std::move(write), extension, info, crf, std::move(origin));
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const hydrolux::io::VideoApi* hydrolux_video_api_v1() {
  static const hydrolux::io::VideoApi api{&open_reader, &open_writer};
  return &api;
}
