#include "hydrolux/io/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "io/png_codec.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

namespace {

// OpenImageIO's name for each format's reader and writer.
const char* oiio_format(ImageFormat f) {
  switch (f) {
    case ImageFormat::png: return "png";
    case ImageFormat::exr: return "openexr";
    case ImageFormat::hdr: return "hdr";
    case ImageFormat::pnm: return "pnm";
    case ImageFormat::jpeg: return "jpeg";
    case ImageFormat::tiff: return "tiff";
  }
  return "";
}

// Joins the lines of a library's message into one, without repeats or empty lines.
void add_lines(std::vector<std::string>& out, std::string_view text) {
  std::size_t start = 0;
  while (start <= text.size()) {
    auto end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string line(text.substr(start, end - start));
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    // Nothing printable is kept: a corrupt file must not reach the terminal through a message.
    for (char& c : line)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    if (line.size() > 200) line = line.substr(0, 200) + "...";
    if (!line.empty() && std::find(out.begin(), out.end(), line) == out.end()) out.push_back(line);
    start = end + 1;
  }
}

// One reason from what OpenImageIO and the codec said: their prefixes dropped ("libpng error: ",
// "PNG read error: "), generic trailers dropped, and a line that another line contains left out.
std::string join(std::vector<std::string> lines) {
  for (auto& l : lines)
    for (std::string_view prefix : {"libpng error: ", "libpng warning: ", "PNG read error: "})
      if (l.rfind(prefix, 0) == 0) l.erase(0, prefix.size());
  lines.erase(std::remove(lines.begin(), lines.end(), std::string("PNG library error")), lines.end());
  std::string s;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    bool covered = false;
    for (std::size_t j = 0; j < lines.size() && !covered; ++j)
      covered = j != i && lines[j].find(lines[i]) != std::string::npos && (lines[j] != lines[i] || j < i);
    if (!covered) s += (s.empty() ? "" : "; ") + lines[i];
  }
  return s;
}

// Redirects file descriptor 2 into an in-memory file while a codec runs, so that what libpng and
// friends print ("libpng error: ...") becomes part of our one-line message instead of stray lines.
// Process-wide, so decoding is serialised by a lock.
class CapturedStderr {
 public:
  CapturedStderr() {
    std::fflush(stderr);
    std::cerr.flush();
    capture_ = ::memfd_create("hydrolux-codec-messages", MFD_CLOEXEC);
    if (capture_ < 0) return;
    saved_ = ::dup(STDERR_FILENO);
    if (saved_ < 0 || ::dup2(capture_, STDERR_FILENO) < 0) {
      if (saved_ >= 0) ::close(saved_);
      ::close(capture_);
      saved_ = capture_ = -1;
    }
  }
  ~CapturedStderr() { (void)finish(); }
  CapturedStderr(const CapturedStderr&) = delete;
  CapturedStderr& operator=(const CapturedStderr&) = delete;

  // Restores stderr and returns what was printed meanwhile, line by line.
  std::vector<std::string> finish() {
    std::vector<std::string> lines;
    if (capture_ < 0) return lines;
    std::fflush(stderr);
    std::cerr.flush();
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
    std::string text;
    char buf[4096];
    if (::lseek(capture_, 0, SEEK_SET) == 0) {
      ssize_t n;
      while (text.size() < 65536 && (n = ::read(capture_, buf, sizeof buf)) > 0) text.append(buf, std::size_t(n));
    }
    ::close(capture_);
    saved_ = capture_ = -1;
    add_lines(lines, text);
    return lines;
  }

 private:
  int saved_ = -1, capture_ = -1;
};

std::mutex& decode_mutex() {
  static std::mutex m;
  return m;
}

// ---- the sRGB curve by table (the same values as color::srgb_encode / srgb_decode) ----

// 8-bit codes from linear floats. The code of a float x, std::lround(srgb_encode(double(x)) * 255),
// never decreases as x grows, so it is fixed by the 255 floats at which it steps: first_[k], the
// least float of code k or more. A float in (0, 1) is found by its bit pattern, which orders the
// positive floats: start_ holds the code of the first float of each run of 2^15 patterns (a run
// spans less than one code: a relative width of at most 2^-8, over which the code grows by at most
// 1.055 * 255 / 2.4 * 2^-8 < 0.5, so it holds at most one step), and one comparison with first_
// finishes it. The same code as the curve for every float: tests/io/test_image_io.cpp sweeps them
// (all 1,065,353,217 in [0, 1] with HYDROLUX_TEST_EXHAUSTIVE=1).
class Srgb8Encoder {
 public:
  static constexpr int kShift = 15;
  static constexpr std::uint32_t kOne = 0x3F800000u;  // the bits of 1.0f

  Srgb8Encoder() : start_((kOne >> kShift) + 1) {
    const auto code = [](std::uint32_t bits) {
      return int(std::lround(color::srgb_encode(double(std::bit_cast<float>(bits))) * 255.0));
    };
    first_.fill(std::numeric_limits<float>::infinity());
    for (int k = 1; k <= 255; ++k) {  // the least bit pattern in [0, 1] whose code is >= k
      std::uint32_t lo = 0, hi = kOne;  // code(lo) < k <= code(hi)
      while (hi - lo > 1) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        (code(mid) >= k ? hi : lo) = mid;
      }
      first_[std::size_t(k)] = std::bit_cast<float>(hi);
    }
    int k = 0;
    for (std::size_t i = 0; i < start_.size(); ++i) {
      const float x = std::bit_cast<float>(std::uint32_t(i) << kShift);
      while (k < 255 && x >= first_[std::size_t(k) + 1]) ++k;
      start_[i] = std::uint8_t(k);
    }
    // No run holds two steps (the bound above): the next step after a run's first code lies beyond
    // the run's last float.
    for (std::size_t i = 0; i + 1 < start_.size(); ++i) {
      const float last = std::bit_cast<float>((std::uint32_t(i + 1) << kShift) - 1);
      if (start_[i] < 254 && last >= first_[std::size_t(start_[i]) + 2])
        throw std::logic_error("Srgb8Encoder: a run of floats holds two steps of the code");
    }
  }

  std::uint8_t operator()(float x) const noexcept {
    if (!(x > 0.0f)) return 0;  // NaN too, as srgb_encode
    if (x >= 1.0f) return 255;
    // A run holds at most one step: one comparison, without a branch (first_[256] is infinite).
    const std::size_t k = start_[std::bit_cast<std::uint32_t>(x) >> kShift];
    return std::uint8_t(k + std::size_t(x >= first_[k + 1]));
  }

 private:
  std::array<float, 257> first_{};
  std::vector<std::uint8_t> start_;
};

const Srgb8Encoder& srgb8_encoder() {
  static const Srgb8Encoder e;
  return e;
}

// Linear floats from 8- and 16-bit codes: OpenImageIO's value of each code (its conversion of the
// code to float, as read_image(FLOAT) converts) and color::srgb_decode<float> of it, for every code.
struct SrgbDecodeTable {
  std::vector<float> value, linear;
  explicit SrgbDecodeTable(OIIO::TypeDesc type) {
    const std::size_t n = type == OIIO::TypeDesc::UINT8 ? 256 : 65536;
    std::vector<std::uint16_t> codes16(n);
    std::vector<std::uint8_t> codes8(n);
    for (std::size_t i = 0; i < n; ++i) codes16[i] = std::uint16_t(i), codes8[i] = std::uint8_t(i);
    value.resize(n);
    linear.resize(n);
    const void* src = n == 256 ? static_cast<const void*>(codes8.data()) : static_cast<const void*>(codes16.data());
    OIIO::convert_pixel_values(type, src, OIIO::TypeDesc::FLOAT, value.data(), int(n));
    for (std::size_t i = 0; i < n; ++i) linear[i] = color::srgb_decode(value[i]);
  }
};

const SrgbDecodeTable& srgb_decode_table(bool sixteen) {
  static const SrgbDecodeTable t8(OIIO::TypeDesc::UINT8);
  static const SrgbDecodeTable t16(OIIO::TypeDesc::UINT16);
  return sixteen ? t16 : t8;
}

// A coded image (8 or 16 bits) read as its codes and turned into linear floats by table: the same
// floats as reading it as FLOAT and applying srgb_decode to each colour value (alpha kept linear);
// with `linear` (a file that declares linear codes) every value as read as FLOAT, without the curve.
template <typename Code>
bool read_coded(OIIO::ImageInput& in, int alpha, Image& img, bool linear_codes) {
  const std::size_t c = std::size_t(img.channels);
  std::vector<Code> codes(img.pixels.size());
  const OIIO::TypeDesc type = sizeof(Code) == 1 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16;
  if (!in.read_image(0, 0, 0, int(c), type, codes.data())) return false;
  const SrgbDecodeTable& t = srgb_decode_table(sizeof(Code) == 2);
  const float* linear = linear_codes ? t.value.data() : t.linear.data();
  const float* value = t.value.data();
  float* out = img.pixels.data();
  if (alpha < 0 || alpha >= int(c)) {
    for (std::size_t i = 0; i < codes.size(); ++i) out[i] = linear[codes[i]];
  } else {
    for (std::size_t i = 0; i < codes.size(); ++i) out[i] = (i % c == std::size_t(alpha) ? value : linear)[codes[i]];
  }
  return true;
}

// PNG stores colour unassociated with alpha; hydrolux's RGBA images hold it multiplied by the
// alpha (a drop's coverage over black). The 4th channel's colour is divided by it, in linear light,
// before the curve (a pixel of alpha 0 holds black); alpha itself is stored linearly.
float straight(const float* pixel, int c) {
  const float a = pixel[3];
  return a > 0.0f ? pixel[c] / a : 0.0f;
}

template <typename T>
std::vector<T> quantise_srgb(const Image& img, double max_code) {
  std::vector<T> out(img.pixels.size());
  const std::size_t c = std::size_t(img.channels);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float* pixel = img.pixels.data() + i / c * c;
    const double v = c != 4         ? color::srgb_encode(double(img.pixels[i]))
                     : i % 4 == 3 ? std::clamp(double(img.pixels[i]), 0.0, 1.0)
                                  : color::srgb_encode(double(straight(pixel, int(i % 4))));
    out[i] = static_cast<T>(std::lround(v * max_code));
  }
  return out;
}

// Data that is not colour (Image::non_colour): every value clamped to [0, 1] and quantised linearly.
template <typename T>
std::vector<T> quantise_linear(const Image& img, double max_code) {
  std::vector<T> out(img.pixels.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = static_cast<T>(std::lround(std::clamp(double(img.pixels[i]), 0.0, 1.0) * max_code));  // NaN: 0
  return out;
}

// 8-bit codes through the encoder's table, as quantise_srgb.
std::vector<std::uint8_t> quantise_srgb8(const Image& img) {
  std::vector<std::uint8_t> out(img.pixels.size());
  const Srgb8Encoder& encode = srgb8_encoder();
  const float* px = img.pixels.data();
  if (img.channels != 4) {
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = encode(px[i]);
  } else {
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = i % 4 == 3 ? std::uint8_t(std::lround(std::clamp(double(px[i]), 0.0, 1.0) * 255.0))
                          : encode(straight(px + i / 4 * 4, int(i % 4)));
  }
  return out;
}

}  // namespace

std::uint8_t srgb8_code(float linear) noexcept { return srgb8_encoder()(linear); }

void srgb8_codes(const float* linear, std::size_t n, std::uint8_t* codes) noexcept {
  const Srgb8Encoder& encode = srgb8_encoder();
  for (std::size_t i = 0; i < n; ++i) codes[i] = encode(linear[i]);
}

DecodedImage decode_image(std::string_view bytes, std::string_view origin, const ImageLimits& limits) {
  const auto fail = [&](const std::string& why) { return IoError(fmt::format("{}: {}", origin, why)); };
  if (bytes.size() > limits.max_file_bytes)
    throw fail(fmt::format("{} bytes, more than the limit of {} bytes", bytes.size(), limits.max_file_bytes));
  const auto format = sniff_image_format(bytes);
  if (!format) throw fail("not an image hydrolux reads (PNG, EXR, Radiance HDR, PNM, JPEG or TIFF)");

  DecodedImage result;
  result.format = *format;
  // The codecs trust their headers: each file's structure is walked first (image_format.cpp). A
  // truncated PNG, for one, would otherwise reach OpenImageIO 2.4's PNG reader, which leaks the
  // error message that libpng's longjmp skips (fuzz/lsan.supp).
  if (const std::string problem = image_structure_problem(*format, bytes, limits); !problem.empty())
    throw fail(fmt::format("malformed, truncated or oversized {} file: {}", format_name(*format), problem));

  // What the header claims against the limits, before any pixel is allocated.
  const auto check_claim = [&](std::int64_t w, std::int64_t h, std::int64_t c) {
    if (w <= 0 || h <= 0 || c <= 0) throw fail(fmt::format("the header claims an empty image ({} x {} x {})", w, h, c));
    const std::string claim = fmt::format("the header claims {} x {} pixels x {} channels", w, h, c);
    if (w > limits.max_side || h > limits.max_side)
      throw fail(fmt::format("{}; the limit is {} pixels a side", claim, limits.max_side));
    if (w * h > limits.max_pixels) throw fail(fmt::format("{}; the limit is {} pixels", claim, limits.max_pixels));
    if (c > limits.max_channels) throw fail(fmt::format("{}; the limit is {} channels", claim, limits.max_channels));
    if (w * h * c > limits.max_values)
      throw fail(fmt::format("{} ({} values); the limit is {} values", claim, w * h * c, limits.max_values));
    if (limits.before_pixels) limits.before_pixels(w, h, c);
    return claim;
  };

  // Plain 8- and 16-bit grey or RGB PNGs (cameras', renderers', hydrolux's own) through libdeflate
  // without the codec's lock; the same floats as OpenImageIO's reader gives (tests/io/test_png.cpp).
  // Anything else, or a file the fast reader finds bad, goes to OpenImageIO below.
  if (*format == ImageFormat::png) {
    if (const auto header = png::plain_header(bytes)) {
      check_claim(header->width, header->height, header->channels);
      std::vector<std::uint8_t> samples;
      if (png::read_samples(bytes, *header, samples)) {
        Image img(header->width, header->height, header->channels);
        // A file that declares linear codes (hydrolux's masks) as code / max, others through the curve.
        const SrgbDecodeTable& table = srgb_decode_table(header->bits == 16);
        const float* linear = header->linear ? table.value.data() : table.linear.data();
        float* out = img.pixels.data();
        if (header->bits == 8) {
          for (std::size_t i = 0; i < img.pixels.size(); ++i) out[i] = linear[samples[i]];
        } else {
          for (std::size_t i = 0; i < img.pixels.size(); ++i)
            out[i] = linear[std::size_t(samples[2 * i]) << 8 | samples[2 * i + 1]];
        }
        result.channel_names = header->channels == 3 ? std::vector<std::string>{"R", "G", "B"}
                                                     : std::vector<std::string>{"Y"};
        result.image = std::move(img);
        result.linear = header->linear;
        return result;
      }
    }
  }

  std::lock_guard lock(decode_mutex());
  CapturedStderr captured;
  std::vector<std::string> why;
  const auto codec_failure = [&](const std::string& oiio_message) {
    add_lines(why, oiio_message);
    for (const auto& l : captured.finish()) why.push_back(l);
    const std::string reason = join(why);
    return fail(fmt::format("cannot read the {} data: {}", format_name(*format), reason.empty() ? "malformed" : reason));
  };

  std::string stripped;
  if (*format == ImageFormat::jpeg) {
    stripped = jpeg_without_metadata(bytes);
    bytes = stripped;
  }

  auto in = OIIO::ImageInput::create(oiio_format(*format));
  if (!in) throw codec_failure(OIIO::geterror());
  OIIO::Filesystem::IOMemReader proxy(const_cast<char*>(bytes.data()), bytes.size());
  OIIO::ImageSpec config;
  void* proxy_ptr = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  OIIO::ImageSpec spec;
  if (!in->open(std::string(origin), spec, config)) throw codec_failure(in->geterror());

  const std::int64_t w = spec.width, h = spec.height, c = spec.nchannels;
  if (spec.deep) throw fail("deep images are not supported");
  const std::string claim = check_claim(w, h, c);
  const int bits = int(spec.format.size() * 8);
  const bool walked = *format != ImageFormat::hdr && *format != ImageFormat::pnm;  // bounded above
  const std::uint64_t least =
      walked ? 0 : min_encoded_bytes(*format, w, h, int(c), bits, bytes.size() > 1 ? bytes[1] : '6');
  if (least > bytes.size())
    throw fail(fmt::format("{}, which needs at least {} bytes of {} data, but the file has {}", claim, least,
                           format_name(*format), bytes.size()));

  Image img(static_cast<int>(w), static_cast<int>(h), static_cast<int>(c));
  // 8- and 16-bit codes (PNG, JPEG, PNM, most TIFF) through the decode tables; other types as floats
  // through the curve.
  const bool one_type = spec.channelformats.empty();
  const bool coded8 = one_type && spec.format == OIIO::TypeDesc::UINT8;
  const bool coded16 = one_type && spec.format == OIIO::TypeDesc::UINT16;
  // A PNG that declares linear codes (gAMA 1.0, no sRGB chunk) is read without the curve, as the
  // fast reader reads it; float formats are linear.
  const bool linear_codes = *format == ImageFormat::png && png::declares_linear(bytes);
  const bool read = coded8    ? read_coded<std::uint8_t>(*in, spec.alpha_channel, img, linear_codes)
                    : coded16 ? read_coded<std::uint16_t>(*in, spec.alpha_channel, img, linear_codes)
                              : in->read_image(0, 0, 0, int(c), OIIO::TypeDesc::FLOAT, img.pixels.data());
  if (!read) throw codec_failure(in->geterror());
  in->close();
  result.warnings = captured.finish();
  result.channel_names.assign(spec.channelnames.begin(), spec.channelnames.end());
  result.linear = linear_codes || spec.format.is_floating_point();
  if (!spec.format.is_floating_point() && !coded8 && !coded16 && !linear_codes) {
    const int alpha = spec.alpha_channel;
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
      if (int(i % std::size_t(c)) != alpha) img.pixels[i] = float(color::srgb_decode(img.pixels[i]));
  }
  result.image = std::move(img);
  return result;
}

std::string encode_image(const Image& image, ImageFormat format, PngOptions png) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0 ||
      image.pixels.size() != std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels))
    throw IoError("cannot encode an image of inconsistent dimensions");
  if (format != ImageFormat::png && format != ImageFormat::exr)
    throw IoError(fmt::format("cannot write {} images (use .exr or .png)", format_name(format)));
  if (format == ImageFormat::png && png.bits != 8 && png.bits != 16)
    throw IoError(fmt::format("PNG bit depth {} (use 8 or 16)", png.bits));
  if (format == ImageFormat::png && (png.compression < 0 || png.compression > kMaxPngCompression))
    throw IoError(fmt::format("PNG compression level {} (use 0 to {})", png.compression, kMaxPngCompression));

  if (format == ImageFormat::png) {
    const bool linear = image.non_colour;  // data: linear codes, gAMA 1.0 and no sRGB chunk
    if (png.bits == 8)
      return png::encode((linear ? quantise_linear<std::uint8_t>(image, 255.0) : quantise_srgb8(image)).data(),
                         image.width, image.height, image.channels, 8, png.compression, linear);
    const std::vector<std::uint16_t> codes =
        linear ? quantise_linear<std::uint16_t>(image, 65535.0) : quantise_srgb<std::uint16_t>(image, 65535.0);
    std::vector<std::uint8_t> big_endian(2 * codes.size());
    for (std::size_t i = 0; i < codes.size(); ++i)
      big_endian[2 * i] = std::uint8_t(codes[i] >> 8), big_endian[2 * i + 1] = std::uint8_t(codes[i]);
    return png::encode(big_endian.data(), image.width, image.height, image.channels, 16, png.compression, linear);
  }

  const OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT;
  const void* data = image.pixels.data();
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput proxy(buffer);
  auto out = OIIO::ImageOutput::create(oiio_format(format));
  if (!out) throw IoError(fmt::format("cannot encode {}: {}", format_name(format), OIIO::geterror()));
  OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
  spec.attribute("oiio:ColorSpace", "linear");
  if (!image.channel_names.empty()) {
    if (image.channel_names.size() != std::size_t(image.channels))
      throw IoError("cannot encode an image whose channel names do not match its channels");
    spec.channelnames = image.channel_names;
    const auto a = std::find(image.channel_names.begin(), image.channel_names.end(), "A");
    spec.alpha_channel = a == image.channel_names.end() ? -1 : int(a - image.channel_names.begin());
  }
  spec.attribute("compression", "zip");
  // Same image, same bytes: OpenImageIO stamps EXR files with the time of writing unless
  // DateTime is set; an empty one is written as an empty capDate.
  spec.attribute("DateTime", "");
  void* proxy_ptr = &proxy;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  if (!out->open("memory", spec) || !out->write_image(type, data) || !out->close()) {
    std::vector<std::string> why;
    add_lines(why, out->geterror());
    throw IoError(fmt::format("cannot encode {}: {}", format_name(format), join(why)));
  }
  return std::string(buffer.begin(), buffer.end());
}

Image read_image(const fs::path& path, const ImageLimits& limits, std::string_view label) {
  const std::string bytes = read_file(path, limits.max_file_bytes, label);
  const std::string origin = label.empty() ? fmt::format("'{}'", path.string()) : fmt::format("{} {}", label, path.string());
  return decode_image(bytes, origin, limits).image;
}

void write_image(const fs::path& path, const Image& image, PngOptions png) {
  const ImageFormat format = output_image_format(path);
  OutputFile out(path);  // reserved (and checked) before encoding
  out.write(encode_image(image, format, png));
  out.commit();
}

}  // namespace hydrolux::io
