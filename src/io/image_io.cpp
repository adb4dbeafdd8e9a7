#include "hydrolux/io/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <mutex>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"

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

template <typename T>
std::vector<T> quantise_srgb(const Image& img, double max_code) {
  std::vector<T> out(img.pixels.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    // Alpha (4th channel) is stored linearly, colour through the sRGB curve.
    const bool alpha = img.channels == 4 && i % 4 == 3;
    const double v = alpha ? std::clamp(double(img.pixels[i]), 0.0, 1.0) : color::srgb_encode(double(img.pixels[i]));
    out[i] = static_cast<T>(std::lround(v * max_code));
  }
  return out;
}

}  // namespace

DecodedImage decode_image(std::string_view bytes, std::string_view origin, const ImageLimits& limits) {
  const auto fail = [&](const std::string& why) { return IoError(fmt::format("{}: {}", origin, why)); };
  if (bytes.size() > limits.max_file_bytes)
    throw fail(fmt::format("{} bytes, more than the limit of {} bytes", bytes.size(), limits.max_file_bytes));
  const auto format = sniff_image_format(bytes);
  if (!format) throw fail("not an image hydrolux reads (PNG, EXR, Radiance HDR, PNM, JPEG or TIFF)");

  std::lock_guard lock(decode_mutex());
  DecodedImage result;
  result.format = *format;
  CapturedStderr captured;
  std::vector<std::string> why;
  const auto codec_failure = [&](const std::string& oiio_message) {
    add_lines(why, oiio_message);
    for (const auto& l : captured.finish()) why.push_back(l);
    const std::string reason = join(why);
    return fail(fmt::format("cannot read the {} data: {}", format_name(*format), reason.empty() ? "malformed" : reason));
  };

  // The codecs trust their headers: each file's structure is walked first (image_format.cpp). A
  // truncated PNG, for one, would otherwise reach OpenImageIO 2.4's PNG reader, which leaks the
  // error message that libpng's longjmp skips (fuzz/lsan.supp).
  if (const std::string problem = image_structure_problem(*format, bytes, limits); !problem.empty())
    throw fail(fmt::format("malformed, truncated or oversized {} file: {}", format_name(*format), problem));

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
  if (w <= 0 || h <= 0 || c <= 0) throw fail(fmt::format("the header claims an empty image ({} x {} x {})", w, h, c));
  const std::string claim = fmt::format("the header claims {} x {} pixels x {} channels", w, h, c);
  if (w > limits.max_side || h > limits.max_side)
    throw fail(fmt::format("{}; the limit is {} pixels a side", claim, limits.max_side));
  if (w * h > limits.max_pixels) throw fail(fmt::format("{}; the limit is {} pixels", claim, limits.max_pixels));
  if (c > limits.max_channels) throw fail(fmt::format("{}; the limit is {} channels", claim, limits.max_channels));
  if (w * h * c > limits.max_values)
    throw fail(fmt::format("{} ({} values); the limit is {} values", claim, w * h * c, limits.max_values));
  const int bits = int(spec.format.size() * 8);
  const bool walked = *format != ImageFormat::hdr && *format != ImageFormat::pnm;  // bounded above
  const std::uint64_t least =
      walked ? 0 : min_encoded_bytes(*format, w, h, int(c), bits, bytes.size() > 1 ? bytes[1] : '6');
  if (least > bytes.size())
    throw fail(fmt::format("{}, which needs at least {} bytes of {} data, but the file has {}", claim, least,
                           format_name(*format), bytes.size()));

  Image img(static_cast<int>(w), static_cast<int>(h), static_cast<int>(c));
  if (!in->read_image(0, 0, 0, int(c), OIIO::TypeDesc::FLOAT, img.pixels.data()))
    throw codec_failure(in->geterror());
  in->close();
  result.warnings = captured.finish();
  result.channel_names.assign(spec.channelnames.begin(), spec.channelnames.end());
  if (!spec.format.is_floating_point()) {
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

  OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT;
  std::vector<std::uint8_t> px8;
  std::vector<std::uint16_t> px16;
  const void* data = image.pixels.data();
  if (format == ImageFormat::png) {
    if (png.bits == 8) {
      px8 = quantise_srgb<std::uint8_t>(image, 255.0);
      type = OIIO::TypeDesc::UINT8;
      data = px8.data();
    } else {
      px16 = quantise_srgb<std::uint16_t>(image, 65535.0);
      type = OIIO::TypeDesc::UINT16;
      data = px16.data();
    }
  }
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput proxy(buffer);
  auto out = OIIO::ImageOutput::create(oiio_format(format));
  if (!out) throw IoError(fmt::format("cannot encode {}: {}", format_name(format), OIIO::geterror()));
  OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
  spec.attribute("oiio:ColorSpace", format == ImageFormat::png ? "sRGB" : "linear");
  if (format == ImageFormat::exr && !image.channel_names.empty()) {
    if (image.channel_names.size() != std::size_t(image.channels))
      throw IoError("cannot encode an image whose channel names do not match its channels");
    spec.channelnames = image.channel_names;
    const auto a = std::find(image.channel_names.begin(), image.channel_names.end(), "A");
    spec.alpha_channel = a == image.channel_names.end() ? -1 : int(a - image.channel_names.begin());
  }
  if (format == ImageFormat::exr) {
    spec.attribute("compression", "zip");
    // Same image, same bytes: OpenImageIO stamps EXR files with the time of writing unless
    // DateTime is set; an empty one is written as an empty capDate.
    spec.attribute("DateTime", "");
  }
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
