// Image formats without OpenImageIO: naming, sniffing, size bounds and output extensions (so that
// the CLI and the fuzzers use them without loading the codecs).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/image_io.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

std::uint64_t ceil_div(std::uint64_t a, std::uint64_t b) { return (a + b - 1) / b; }

}  // namespace

std::string_view format_name(ImageFormat f) {
  switch (f) {
    case ImageFormat::png: return "PNG";
    case ImageFormat::exr: return "OpenEXR";
    case ImageFormat::hdr: return "Radiance HDR";
    case ImageFormat::pnm: return "PNM";
    case ImageFormat::jpeg: return "JPEG";
    case ImageFormat::tiff: return "TIFF";
  }
  return "?";
}

std::optional<ImageFormat> sniff_image_format(std::string_view b) {
  const auto starts = [&](std::string_view magic) { return b.substr(0, magic.size()) == magic; };
  if (starts("\x89PNG\r\n\x1a\n")) return ImageFormat::png;
  if (starts(std::string_view("\x76\x2f\x31\x01", 4))) return ImageFormat::exr;
  if (starts("#?RADIANCE") || starts("#?RGBE")) return ImageFormat::hdr;
  if (starts("\xff\xd8\xff")) return ImageFormat::jpeg;
  if (starts(std::string_view("II*\0", 4)) || starts(std::string_view("MM\0*", 4))) return ImageFormat::tiff;
  if (b.size() >= 3 && b[0] == 'P' && std::string_view("123456fF").find(b[1]) != std::string_view::npos &&
      std::isspace(static_cast<unsigned char>(b[2])))
    return ImageFormat::pnm;
  return std::nullopt;
}

std::uint64_t min_encoded_bytes(ImageFormat f, std::int64_t width, std::int64_t height, int channels, int bits,
                                char pnm_magic) {
  const auto w = std::uint64_t(width), h = std::uint64_t(height), c = std::uint64_t(channels);
  switch (f) {
    case ImageFormat::png: {
      // zlib's deflate expands at most 1032:1 (its documented limit); each row is a filter byte
      // plus its packed samples.
      const std::uint64_t raw = h * (1 + ceil_div(w * c * std::uint64_t(bits), 8));
      return raw / 1032;
    }
    case ImageFormat::pnm:
      switch (pnm_magic) {
        case '1': return w * h;                      // one digit a pixel (whitespace optional)
        case '4': return h * ceil_div(w, 8);         // packed bits
        case '2':
        case '3': return 2 * w * h * c - 1;          // a digit and a separator a value
        case 'f':
        case 'F': return 4 * w * h * c;              // 32-bit floats
        default: return w * h * c * (bits > 8 ? 2 : 1);  // P5, P6 binary
      }
    case ImageFormat::hdr:
      // Scanlines of 8-32767 pixels may be run-length encoded: a 4-byte header and, for each of
      // the four components, runs of at most 127 bytes in 2 bytes. Others are flat RGBE.
      if (w >= 8 && w <= 0x7fff) return h * (4 + 4 * 2 * ceil_div(w, 127));
      return 4 * w * h;
    case ImageFormat::jpeg:
      // Every 8x8 block of the first component costs at least one bit of DC code.
      return ceil_div(ceil_div(w, 8) * ceil_div(h, 8), 8);
    case ImageFormat::exr:
    case ImageFormat::tiff: return 0;
  }
  return 0;
}

ImageFormat output_image_format(const fs::path& path, std::string_view label) {
  const std::string ext = lower_extension(path);
  if (ext == ".png") return ImageFormat::png;
  if (ext == ".exr") return ImageFormat::exr;
  throw IoError(fmt::format("{}{}{}: the output must be a .png or .exr file", label, label.empty() ? "'" : " ",
                            path.string() + (label.empty() ? "'" : "")));
}

std::string png_structure_problem(std::string_view b) {
  constexpr std::size_t kSignature = 8;
  if (b.size() < kSignature) return "the file ends inside the PNG signature";
  std::size_t pos = kSignature;
  bool first = true;
  while (true) {
    if (b.size() - pos < 8) return pos == b.size() ? "the file ends before the IEND chunk" : "the file ends inside a chunk header";
    const auto u = [&](std::size_t i) { return std::uint32_t(static_cast<unsigned char>(b[pos + i])); };
    const std::uint32_t length = u(0) << 24 | u(1) << 16 | u(2) << 8 | u(3);
    std::string type(b.substr(pos + 4, 4));
    for (char& c : type)
      if (!std::isalpha(static_cast<unsigned char>(c))) c = '?';
    if (length > 0x7fffffffu) return fmt::format("the {} chunk claims {} bytes, more than PNG allows", type, length);
    if (first && type != "IHDR") return "the first chunk is not IHDR";
    first = false;
    if (b.size() - pos - 8 < std::uint64_t(length) + 4)
      return fmt::format("the file ends inside the {} chunk (it claims {} bytes)", type, length);
    pos += 8 + std::size_t(length) + 4;
    if (type == "IEND") return {};
  }
}

}  // namespace hydrolux::io
