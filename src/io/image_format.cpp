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

std::string exr_header_problem(std::string_view b, const ImageLimits& limits) {
  // Flags in the version field (OpenEXR file layout, "Version Field").
  constexpr std::uint32_t kTiled = 0x200, kLongNames = 0x400, kNonImage = 0x800, kMultipart = 0x1000;
  if (b.size() < 8) return "the file ends inside the EXR magic number and version";
  const auto u32 = [&](std::size_t at) {
    return std::uint32_t(static_cast<unsigned char>(b[at])) | std::uint32_t(static_cast<unsigned char>(b[at + 1])) << 8 |
           std::uint32_t(static_cast<unsigned char>(b[at + 2])) << 16 |
           std::uint32_t(static_cast<unsigned char>(b[at + 3])) << 24;
  };
  const auto i32 = [&](std::size_t at) { return std::int32_t(u32(at)); };
  const std::uint32_t version = u32(4);
  if ((version & 0xff) != 2) return fmt::format("EXR version {} (hydrolux reads version 2)", version & 0xff);
  if (version & kNonImage) return "deep (non-image) EXR data is not supported";
  const std::size_t max_name = (version & kLongNames) ? 255 : 31;
  std::size_t pos = 8;
  // A NUL-terminated name of at most max_name characters.
  const auto read_name = [&](std::string& out) -> std::string {
    const auto end = b.find('\0', pos);
    if (end == std::string_view::npos) return "the file ends inside an attribute name";
    if (end - pos > max_name) return fmt::format("an attribute name longer than {} characters", max_name);
    out.assign(b.substr(pos, end - pos));
    pos = end + 1;
    return {};
  };
  std::uint64_t chunks = 0;
  for (int part = 0;; ++part) {
    if (part > 0) {  // multipart: the list of headers ends with an empty one
      if (pos >= b.size()) return "the file ends inside the part headers";
      if (b[pos] == '\0') {
        ++pos;
        break;
      }
    }
    if (part >= 1024) return "more than 1024 parts";
    bool have_window = false, have_channels = false, tiled = (version & kTiled) != 0;
    std::int64_t w = 0, h = 0;
    std::uint32_t tile_x = 0, tile_y = 0;
    int compression = 0;
    std::int64_t chunk_count = -1;
    for (int attributes = 0;; ++attributes) {
      std::string name, type;
      if (auto e = read_name(name); !e.empty()) return e;
      if (name.empty()) break;
      if (attributes >= 4096) return "more than 4096 attributes";
      if (auto e = read_name(type); !e.empty()) return e;
      if (b.size() - pos < 4) return fmt::format("the file ends inside the size of attribute '{}'", name);
      const std::int32_t size = i32(pos);
      pos += 4;
      if (size < 0 || std::uint64_t(size) > b.size() - pos)
        return fmt::format("attribute '{}' claims {} bytes, more than the {} left in the file", name, size,
                           b.size() - pos);
      if (name == "dataWindow" && type == "box2i" && size == 16) {
        const std::int64_t xmin = i32(pos), ymin = i32(pos + 4), xmax = i32(pos + 8), ymax = i32(pos + 12);
        w = xmax - xmin + 1;
        h = ymax - ymin + 1;
        have_window = true;
      } else if (name == "compression" && size == 1) {
        compression = static_cast<unsigned char>(b[pos]);
      } else if (name == "tiles" && type == "tiledesc" && size == 9) {
        tile_x = u32(pos);
        tile_y = u32(pos + 4);
        tiled = true;
      } else if (name == "chunkCount" && type == "int" && size == 4) {
        chunk_count = i32(pos);
      } else if (name == "channels" && type == "chlist") {
        // name, pixel type (0 uint, 1 half, 2 float), pLinear, 3 reserved, x and y sampling; a
        // NUL ends the list. OpenImageIO 2.4 aborts on any other pixel type (an assertion left on
        // in release builds: found by fuzz_image).
        std::size_t at = pos, end = pos + std::size_t(size), count = 0;
        while (true) {
          if (at >= end) return "the channel list is not terminated";
          if (b[at] == '\0') break;
          const auto name_end = b.find('\0', at);
          if (name_end == std::string_view::npos || name_end >= end || end - name_end - 1 < 16)
            return "a channel entry runs past its attribute";
          const std::size_t fields = name_end + 1;
          const std::int32_t pixel_type = i32(fields);
          if (pixel_type < 0 || pixel_type > 2) return fmt::format("a channel of unknown pixel type {}", pixel_type);
          if (i32(fields + 8) < 1 || i32(fields + 12) < 1) return "a channel with a sampling rate below 1";
          at = fields + 16;
          if (++count > std::size_t(limits.max_channels))
            return fmt::format("more than {} channels", limits.max_channels);
        }
        if (count == 0) return "no channels";
        have_channels = true;
      } else if (name == "type" && type == "string") {
        const std::string_view t = b.substr(pos, std::size_t(size));
        if (t.substr(0, 4) == "deep") return "deep EXR data is not supported";
      }
      pos += std::size_t(size);
    }
    if (!have_window) return "a part has no dataWindow";
    if (!have_channels) return "a part has no channel list";
    if (w < 1 || h < 1) return fmt::format("the data window is {} x {} pixels", w, h);
    if (w > limits.max_side || h > limits.max_side)
      return fmt::format("the header claims {} x {} pixels; the limit is {} pixels a side", w, h, limits.max_side);
    if (w * h > limits.max_pixels)
      return fmt::format("the header claims {} x {} pixels; the limit is {} pixels", w, h, limits.max_pixels);
    if (chunk_count >= 0) {
      chunks += std::uint64_t(chunk_count);
    } else if (tiled) {
      if (tile_x == 0 || tile_y == 0) return "a tiled part without a valid tile size";
      chunks += ceil_div(std::uint64_t(w), tile_x) * ceil_div(std::uint64_t(h), tile_y);
    } else {
      // Scan lines per chunk by compression: none, RLE, ZIPS 1; ZIP, PXR24 16; PIZ, B44(A), DWAA 32;
      // DWAB (and anything newer, counted generously) 256.
      static constexpr int kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
      const int lines = compression >= 0 && compression < 10 ? kLines[compression] : 256;
      chunks += ceil_div(std::uint64_t(h), std::uint64_t(lines));
    }
    if (!(version & kMultipart)) break;
  }
  if (chunks > (b.size() - pos) / 8)
    return fmt::format("the header asks for {} chunks, whose offset table alone needs {} bytes, but {} are left",
                       chunks, 8 * chunks, b.size() - pos);
  return {};
}

}  // namespace hydrolux::io
