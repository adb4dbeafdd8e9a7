// Image formats without OpenImageIO: naming, sniffing, size bounds and output extensions (so that
// the CLI and the fuzzers use them without loading the codecs).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

namespace {

std::uint64_t ceil_div(std::uint64_t a, std::uint64_t b) { return (a + b - 1) / b; }

std::uint32_t be16_at(std::string_view b, std::size_t at) {
  return std::uint32_t(static_cast<unsigned char>(b[at])) << 8 | std::uint32_t(static_cast<unsigned char>(b[at + 1]));
}

std::uint32_t be32_at(std::string_view b, std::size_t at) { return be16_at(b, at) << 16 | be16_at(b, at + 2); }

// A tile of tw x th pixels for a w x h image: decoders allocate whole tiles, so one may be no larger
// in area than the image rounded up to 16 pixels a side, or 512 x 512 (the largest common tile,
// Cloud-Optimised GeoTIFFs'), whichever is more.
std::string tile_problem(std::uint64_t tw, std::uint64_t th, std::uint64_t w, std::uint64_t h) {
  const std::uint64_t allowed = std::max<std::uint64_t>(ceil_div(w, 16) * 16 * ceil_div(h, 16) * 16, 512 * 512);
  if (tw > 65536 || th > 65536 || tw * th > allowed)
    return fmt::format("tiles of {} x {} pixels for an image of {} x {}", tw, th, w, h);
  return {};
}

// A width x height claim against the limits; empty if within them.
std::string size_problem(std::uint64_t w, std::uint64_t h, const ImageLimits& limits) {
  if (w > std::uint64_t(limits.max_side) || h > std::uint64_t(limits.max_side))
    return fmt::format("the header claims {} x {} pixels; the limit is {} pixels a side", w, h, limits.max_side);
  if (w * h > std::uint64_t(limits.max_pixels))
    return fmt::format("the header claims {} x {} pixels; the limit is {} pixels", w, h, limits.max_pixels);
  return {};
}

// Little-endian 32-bit fields, as OpenEXR stores them.
std::uint32_t le32_at(std::string_view b, std::size_t at) {
  return std::uint32_t(static_cast<unsigned char>(b[at])) | std::uint32_t(static_cast<unsigned char>(b[at + 1])) << 8 |
         std::uint32_t(static_cast<unsigned char>(b[at + 2])) << 16 |
         std::uint32_t(static_cast<unsigned char>(b[at + 3])) << 24;
}
std::int32_t le32s_at(std::string_view b, std::size_t at) { return std::int32_t(le32_at(b, at)); }

// An EXR channel list (attribute `channels`, `size` bytes at `pos`): name, pixel type (0 uint, 1
// half, 2 float), pLinear, 3 reserved, x and y sampling; a NUL ends the list. OpenImageIO 2.4 aborts
// on any other pixel type (an assertion left on in release builds: found by fuzz_image).
std::string exr_channels_problem(std::string_view b, std::size_t pos, std::size_t size, const ImageLimits& limits) {
  std::size_t at = pos, end = pos + size, count = 0;
  while (true) {
    if (at >= end) return "the channel list is not terminated";
    if (b[at] == '\0') break;
    const auto name_end = b.find('\0', at);
    if (name_end == std::string_view::npos || name_end >= end || end - name_end - 1 < 16)
      return "a channel entry runs past its attribute";
    const std::size_t fields = name_end + 1;
    const std::int32_t pixel_type = le32s_at(b, fields);
    if (pixel_type < 0 || pixel_type > 2) return fmt::format("a channel of unknown pixel type {}", pixel_type);
    if (le32s_at(b, fields + 8) < 1 || le32s_at(b, fields + 12) < 1) return "a channel with a sampling rate below 1";
    at = fields + 16;
    if (++count > std::size_t(limits.max_channels)) return fmt::format("more than {} channels", limits.max_channels);
  }
  if (count == 0) return "no channels";
  return {};
}

// The tiles of a w x h part over every level: one level (mode 0); mipmap levels halving both sides
// together (1); ripmap levels halving each side on its own (2); OpenEXR's level rounding, down or up.
std::uint64_t exr_tile_count(std::uint64_t w, std::uint64_t h, std::uint32_t tile_x, std::uint32_t tile_y,
                             int level_mode, int rounding) {
  const auto level_count = [&](std::uint64_t n) {
    int levels = 1;
    while (n > 1) {
      n = rounding ? (n + 1) / 2 : n / 2;
      ++levels;
    }
    return levels;
  };
  const auto level_size = [&](std::uint64_t n, int l) {
    for (int k = 0; k < l; ++k) n = rounding ? (n + 1) / 2 : n / 2;
    return std::max<std::uint64_t>(n, 1);
  };
  const int lx = level_mode == 0 ? 1 : level_count(level_mode == 1 ? std::max(w, h) : w);
  const int ly = level_mode == 0 ? 1 : level_mode == 1 ? lx : level_count(h);
  std::uint64_t chunks = 0;
  for (int i = 0; i < lx; ++i)
    for (int j = 0; j < ly; ++j) {
      if (level_mode == 1 && i != j) continue;
      chunks += ceil_div(level_size(w, i), tile_x) * ceil_div(level_size(h, j), tile_y);
    }
  return chunks;
}


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
  if (starts(std::string_view("II+\0", 4)) || starts(std::string_view("MM\0+", 4))) return ImageFormat::tiff;  // BigTIFF
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
      // plus its packed samples (`bits` a sample as stored: 1-16).
      return (h + w * h * c * std::uint64_t(bits) / 8) / 1032;
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

std::string png_structure_problem(std::string_view b, const ImageLimits& limits) {
  constexpr std::size_t kSignature = 8;
  if (b.size() < kSignature) return "the file ends inside the PNG signature";
  std::size_t pos = kSignature;
  bool first = true;
  std::uint64_t width = 0, height = 0, bits_per_pixel = 0, idat_bytes = 0;
  while (true) {
    if (b.size() - pos < 8) return pos == b.size() ? "the file ends before the IEND chunk" : "the file ends inside a chunk header";
    const std::uint32_t length = be32_at(b, pos);
    std::string type(b.substr(pos + 4, 4));
    for (char& c : type)
      if (!std::isalpha(static_cast<unsigned char>(c))) c = '?';
    if (length > 0x7fffffffu) return fmt::format("the {} chunk claims {} bytes, more than PNG allows", type, length);
    if (first && type != "IHDR") return "the first chunk is not IHDR";
    if (b.size() - pos - 8 < std::uint64_t(length) + 4)
      return fmt::format("the file ends inside the {} chunk (it claims {} bytes)", type, length);
    if (first) {
      // IHDR: width, height, bit depth, colour type (0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA).
      if (length != 13) return "the IHDR chunk is not 13 bytes";
      width = be32_at(b, pos + 8);
      height = be32_at(b, pos + 12);
      const int depth = static_cast<unsigned char>(b[pos + 16]), colour = static_cast<unsigned char>(b[pos + 17]);
      static constexpr int kSamples[] = {1, 0, 3, 1, 2, 0, 4};
      if (colour > 6 || kSamples[colour] == 0) return fmt::format("unknown PNG colour type {}", colour);
      if (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16)
        return fmt::format("PNG bit depth {}", depth);
      bits_per_pixel = std::uint64_t(kSamples[colour]) * std::uint64_t(depth);
      if (width == 0 || height == 0) return fmt::format("the header claims {} x {} pixels", width, height);
      if (const std::string e = size_problem(width, height, limits); !e.empty()) return e;
    }
    first = false;
    if (type == "IDAT") idat_bytes += length;
    pos += 8 + std::size_t(length) + 4;
    if (type == "IEND") break;
  }
  // The IDAT chunks against deflate's best ratio, for the pixels as stored (one "channel" of
  // bits_per_pixel bits; with Adam7 interlacing there are more filter bytes, never fewer).
  const std::uint64_t least =
      min_encoded_bytes(ImageFormat::png, std::int64_t(width), std::int64_t(height), 1, int(bits_per_pixel));
  if (idat_bytes < least)
    return fmt::format(
        "the header claims {} x {} pixels of {} bits, which need at least {} bytes of compressed image data, but the "
        "IDAT chunks hold {}",
        width, height, bits_per_pixel, least, idat_bytes);
  return {};
}

std::string exr_header_problem(std::string_view b, const ImageLimits& limits) {
  // Flags in the version field (OpenEXR file layout, "Version Field").
  constexpr std::uint32_t kTiled = 0x200, kLongNames = 0x400, kNonImage = 0x800, kMultipart = 0x1000;
  if (b.size() < 8) return "the file ends inside the EXR magic number and version";
  const auto u32 = [&](std::size_t at) { return le32_at(b, at); };
  const auto i32 = [&](std::size_t at) { return le32s_at(b, at); };
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
    // A single part is tiled by the version flag (OpenEXR ignores a stray `tiles` attribute); a
    // part of a multipart file by its `type`.
    const bool multipart = (version & kMultipart) != 0;
    bool have_window = false, have_channels = false, tiled = !multipart && (version & kTiled) != 0;
    std::int64_t w = 0, h = 0;
    std::uint32_t tile_x = 0, tile_y = 0;
    int level_mode = 0, rounding = 0;
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
        level_mode = static_cast<unsigned char>(b[pos + 8]) & 0x0f;  // one level, mipmap, ripmap
        rounding = static_cast<unsigned char>(b[pos + 8]) >> 4 & 1;   // down, up
      } else if (name == "chunkCount" && type == "int" && size == 4) {
        chunk_count = i32(pos);
      } else if (name == "channels" && type == "chlist") {
        if (auto e = exr_channels_problem(b, pos, std::size_t(size), limits); !e.empty()) return e;
        have_channels = true;
      } else if (name == "type" && type == "string") {
        const std::string_view t = b.substr(pos, std::size_t(size));
        if (t.substr(0, 4) == "deep") return "deep EXR data is not supported";
        if (multipart && t.substr(0, 10) == "tiledimage") tiled = true;
      }
      pos += std::size_t(size);
    }
    if (!have_window) return "a part has no dataWindow";
    if (!have_channels) return "a part has no channel list";
    if (w < 1 || h < 1) return fmt::format("the data window is {} x {} pixels", w, h);
    if (const std::string e = size_problem(std::uint64_t(w), std::uint64_t(h), limits); !e.empty()) return e;
    std::uint64_t part_chunks = 0;
    if (tiled) {
      if (tile_x == 0 || tile_y == 0) return "a tiled part without a valid tile size";
      // OpenEXR allocates a tile buffer for each of its thread slots: a tile may be no larger
      // than the image (rounded up to 16) or 512 x 512 pixels, whichever is more.
      if (const std::string e = tile_problem(tile_x, tile_y, std::uint64_t(w), std::uint64_t(h)); !e.empty())
        return e;
      if (level_mode > 2) return fmt::format("unknown EXR level mode {}", level_mode);
      part_chunks = exr_tile_count(std::uint64_t(w), std::uint64_t(h), tile_x, tile_y, level_mode, rounding);
    } else {
      // Scan lines per chunk by compression: none, RLE, ZIPS 1; ZIP, PXR24 16; PIZ, B44(A), DWAA 32;
      // DWAB (and anything newer, counted generously) 256.
      static constexpr int kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
      const int lines = compression >= 0 && compression < 10 ? kLines[compression] : 256;
      part_chunks = ceil_div(std::uint64_t(h), std::uint64_t(lines));
    }
    // A multipart file states each part's chunk count; it must be what the part needs.
    if (multipart && (chunk_count < 0 || std::uint64_t(chunk_count) != part_chunks))
      return fmt::format("a part states {} chunks but its data window and tiling need {}", chunk_count, part_chunks);
    chunks += part_chunks;
    if (!(version & kMultipart)) break;
  }
  if (chunks > (b.size() - pos) / 8)
    return fmt::format("the header asks for {} chunks, whose offset table alone needs {} bytes, but {} are left",
                       chunks, 8 * chunks, b.size() - pos);
  // Every chunk lies after the table and inside the file (OpenEXR otherwise seeks to what a zeroed
  // or corrupt table says and sizes its reads from whatever it finds there).
  const std::uint64_t table_end = pos + 8 * chunks;
  for (std::uint64_t k = 0; k < chunks; ++k) {
    const std::uint64_t offset = std::uint64_t(u32(pos + 8 * k)) | std::uint64_t(u32(pos + 8 * k + 4)) << 32;
    if (offset < table_end || offset >= b.size())
      return fmt::format("the offset table puts chunk {} of {} at byte {}, outside the chunk data (bytes {} to {})",
                         k + 1, chunks, offset, table_end, b.size());
  }
  return {};
}

namespace {

// Walks a JPEG (ITU T.81, Annex B) from after SOI to EOI: marker segments (0xFF, a marker, a
// 16-bit length counting itself), entropy-coded data after each SOS up to the next marker other
// than RSTn or a stuffed 0xFF00. Stray bytes between segments are skipped, as libjpeg skips them.
// For each marker, visit(marker, at, payload, end): `at` its first 0xFF, `payload` where its length
// field starts (equal to `end` for TEM, RSTn and EOI, which have none), `end` just past it and,
// for SOS, past its entropy-coded data. The walk stops at EOI, at a malformed or truncated spot
// (returning why), or when the visitor returns a reason.
template <typename Visit>
std::string walk_jpeg(std::string_view b, Visit&& visit) {
  const auto byte = [&](std::size_t at) { return static_cast<unsigned char>(b[at]); };
  // The first 0xFF at or after `from`, or b.size().
  const auto next_ff = [&](std::size_t from) {
    const void* ff = from < b.size() ? std::memchr(b.data() + from, 0xff, b.size() - from) : nullptr;
    return ff ? std::size_t(static_cast<const char*>(ff) - b.data()) : b.size();
  };
  constexpr std::string_view kTruncated = "the file ends before the end-of-image marker (truncated)";
  std::size_t pos = 2;
  while (true) {
    pos = next_ff(pos);
    const std::size_t at = pos;
    while (pos < b.size() && byte(pos) == 0xff) ++pos;  // fill bytes
    if (pos >= b.size()) return std::string(kTruncated);
    const unsigned marker = byte(pos++);
    if (marker == 0xd9) return visit(marker, at, pos, pos);  // EOI
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) {  // TEM, RSTn: no length
      if (std::string e = visit(marker, at, pos, pos); !e.empty()) return e;
      continue;
    }
    if (marker == 0xd8 || marker == 0x00) return fmt::format("an unexpected marker 0x{:02X}", marker);
    if (b.size() - pos < 2) return "the file ends inside a marker segment (truncated)";
    const std::size_t length = be16_at(b, pos);
    if (length < 2 || b.size() - pos < length)
      return fmt::format("the file ends inside a segment: marker 0x{:02X} claims {} bytes (truncated)", marker, length);
    std::size_t end = pos + length;
    if (marker == 0xda) {
      while (true) {
        end = next_ff(end);
        if (end + 1 >= b.size()) return "the file ends inside the image data (truncated)";
        const unsigned next = byte(end + 1);
        if (next == 0x00 || (next >= 0xd0 && next <= 0xd7)) end += 2;  // stuffing, restart marker
        else if (next == 0xff) ++end;                                    // fill before a marker
        else break;
      }
    }
    if (std::string e = visit(marker, at, pos, end); !e.empty()) return e;
    pos = end;
  }
}

}  // namespace

std::string jpeg_structure_problem(std::string_view b, const ImageLimits& limits) {
  if (b.size() < 4 || static_cast<unsigned char>(b[0]) != 0xff || static_cast<unsigned char>(b[1]) != 0xd8)
    return "no JPEG start-of-image marker";
  bool have_frame = false;
  std::uint64_t width = 0, height = 0, scans = 0;
  const std::string problem = walk_jpeg(b, [&](unsigned marker, std::size_t, std::size_t payload, std::size_t) {
    const bool frame = marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (frame) {
      if (have_frame) return std::string("a second frame header");
      if (be16_at(b, payload) < 8) return std::string("a frame header shorter than 8 bytes");
      height = be16_at(b, payload + 3);
      width = be16_at(b, payload + 5);
      const std::uint64_t components = static_cast<unsigned char>(b[payload + 7]);
      if (height == 0) return std::string("the image height is left to a DNL marker (not supported)");
      if (width == 0) return std::string("the header claims a width of 0");
      if (components == 0 || components > std::uint64_t(limits.max_channels))
        return fmt::format("the header claims {} components; the limit is {}", components, limits.max_channels);
      if (std::string e = size_problem(width, height, limits); !e.empty()) return e;
      // Arithmetic coding has no bound of bytes a block: a 114-byte file can make libjpeg decode a
      // 16384 x 16384 progressive image (4.8 GB, 18 s; found in review). It is rare: refused.
      if (marker >= 0xc9) return std::string("arithmetic-coded JPEG is not supported (re-encode it with Huffman coding)");
      have_frame = true;
    } else if (marker == 0xda) {
      if (!have_frame) return std::string("a scan before the frame header");
      if (++scans > std::uint64_t(limits.max_jpeg_scans))
        return fmt::format("more than {} scans (each progressive scan passes over the whole image)",
                           limits.max_jpeg_scans);
    }
    return std::string();
  });
  if (!problem.empty()) return problem;
  if (!have_frame) return "no frame header";
  if (scans == 0) return "no image data (no scan)";
  const std::uint64_t least = min_encoded_bytes(ImageFormat::jpeg, std::int64_t(width), std::int64_t(height), 1, 8);
  if (least > b.size())
    return fmt::format("the header claims {} x {} pixels, which need at least {} bytes of JPEG data, but the file has {}",
                       width, height, least, b.size());
  return {};
}

std::string jpeg_without_metadata(std::string_view b) {
  std::string out(b.substr(0, 2));  // SOI
  out.reserve(b.size());
  // The file passed jpeg_structure_problem: the walk reaches EOI.
  (void)walk_jpeg(b, [&](unsigned marker, std::size_t at, std::size_t, std::size_t end) {
    // APP1-APP13, APP15 (Exif, XMP, ICC, IPTC/Photoshop, ...) and COM are dropped; APP0 (JFIF) and
    // APP14 (Adobe: the colour transform) change how the pixels decode and are kept.
    const bool metadata = (marker >= 0xe1 && marker <= 0xef && marker != 0xee) || marker == 0xfe;
    if (!metadata) out.append(b.substr(at, end - at));
    return std::string();
  });
  return out;
}

std::string tiff_structure_problem(std::string_view b, const ImageLimits& limits) {
  // TIFF 6.0 (and BigTIFF): a byte order mark, 42 (or 43), the offset of the first image file
  // directory (IFD), whose entries are tag, type, count and a value or the offset of the values.
  // Only the first image is read, so only the first IFD is walked.
  if (b.size() < 8) return "the file ends inside the TIFF header";
  const bool little = b[0] == 'I';
  const auto u = [&](std::uint64_t at, int n) {
    std::uint64_t v = 0;
    for (int k = 0; k < n; ++k) {
      const std::uint64_t byte = static_cast<unsigned char>(b[std::size_t(at) + std::size_t(k)]);
      v |= little ? byte << (8 * k) : byte << (8 * (n - 1 - k));
    }
    return v;
  };
  const std::uint64_t version = u(2, 2);
  if (version != 42 && version != 43) return fmt::format("TIFF version {}", version);
  const bool big = version == 43;
  const int word = big ? 8 : 4;  // offsets and counts
  if (big && (b.size() < 16 || u(4, 2) != 8)) return "a malformed BigTIFF header";
  const std::uint64_t ifd = u(big ? 8 : 4, word);
  const std::uint64_t entry_size = big ? 20 : 12, count_size = big ? 8 : 2;
  if (ifd < 8 || ifd > b.size() || b.size() - ifd < count_size)
    return fmt::format("the first image directory is at byte {}, outside the file", ifd);
  const std::uint64_t entries = u(ifd, int(count_size));
  if (entries == 0 || entries > (b.size() - ifd - count_size) / entry_size)
    return fmt::format("the first image directory claims {} entries, more than the file holds", entries);

  struct Field {
    std::uint64_t type_size = 0, count = 0, at = 0;  // `at`: where the values are
    bool present = false;
  };
  // Tags used below: ImageWidth, ImageLength, BitsPerSample, Compression, StripOffsets,
  // SamplesPerPixel, RowsPerStrip, StripByteCounts, PlanarConfiguration, TileWidth, TileLength,
  // TileOffsets, TileByteCounts, and SGI's ImageDepth (volumes).
  enum Tag : std::uint64_t {
    kWidth = 256, kLength = 257, kBits = 258, kCompression = 259, kStripOffsets = 273, kSamples = 277,
    kRowsPerStrip = 278, kStripBytes = 279, kPlanar = 284, kTileWidth = 322, kTileLength = 323,
    kTileOffsets = 324, kTileBytes = 325, kImageDepth = 32997
  };
  constexpr std::uint64_t kTags[] = {kWidth,       kLength,     kBits,     kCompression, kStripOffsets,
                                     kSamples,     kRowsPerStrip, kStripBytes, kPlanar,  kTileWidth,
                                     kTileLength,  kTileOffsets,  kTileBytes,  kImageDepth};
  Field fields[std::size(kTags)];
  for (std::uint64_t k = 0; k < entries; ++k) {
    const std::uint64_t e = ifd + count_size + k * entry_size;
    const std::uint64_t tag = u(e, 2), type = u(e + 2, 2), count = u(e + 4, word);
    // Bytes per value of each TIFF field type (1-12 TIFF 6.0, 13 IFD, 16-18 BigTIFF).
    static constexpr int kTypeSize[] = {0, 1, 1, 2, 4, 8, 1, 1, 2, 4, 8, 4, 8, 4, 0, 0, 8, 8, 8};
    const std::uint64_t type_size = type < std::size(kTypeSize) ? std::uint64_t(kTypeSize[type]) : 0;
    if (type_size == 0) continue;  // unknown types are skipped, as readers do
    if (count > b.size() / type_size)
      return fmt::format("TIFF tag {} claims {} values, more than the file holds", tag, count);
    const std::uint64_t bytes = count * type_size;
    std::uint64_t at = e + 4 + std::uint64_t(word);
    if (bytes > std::uint64_t(word)) {
      at = u(at, word);
      if (at > b.size() || b.size() - at < bytes)
        return fmt::format("the values of TIFF tag {} lie outside the file ({} bytes at byte {})", tag, bytes, at);
    }
    // A repeated tag: libtiff keeps the first and ignores the rest, so the walk does too.
    for (std::size_t i = 0; i < std::size(kTags); ++i)
      if (kTags[i] == tag && !fields[i].present) fields[i] = {type_size, count, at, true};
  }
  const auto field = [&](Tag tag) -> const Field& {
    std::size_t i = 0;
    while (kTags[i] != tag) ++i;
    return fields[i];
  };
  // The i-th value of an integer field.
  const auto value = [&](const Field& f, std::uint64_t i) { return u(f.at + i * f.type_size, int(f.type_size)); };
  const auto scalar = [&](Tag tag, std::uint64_t fallback) {
    const Field& f = field(tag);
    return f.present && f.count >= 1 && f.type_size <= 8 ? value(f, 0) : fallback;
  };
  const std::uint64_t width = scalar(kWidth, 0), height = scalar(kLength, 0);
  if (width == 0 || height == 0) return fmt::format("the header claims {} x {} pixels", width, height);
  if (const std::string e = size_problem(width, height, limits); !e.empty()) return e;
  if (scalar(kImageDepth, 1) != 1) return "TIFF volumes (ImageDepth > 1) are not supported";
  const std::uint64_t samples = scalar(kSamples, 1), bits = scalar(kBits, 1);
  if (samples == 0 || samples > std::uint64_t(limits.max_channels))
    return fmt::format("the header claims {} samples a pixel; the limit is {}", samples, limits.max_channels);
  if (bits == 0 || bits > 64) return fmt::format("{} bits a sample", bits);
  const std::uint64_t planes = scalar(kPlanar, 1) == 2 ? samples : 1;

  // The strips or tiles the image needs, each of which must lie inside the file: a tile may not be
  // larger than the image rounded up to whole 16-pixel tiles (libtiff allocates a whole tile to
  // decode one: a 1 kB file claiming 1-pixel image in 65536 x 65536 tiles asks for gigabytes).
  const bool tiled = field(kTileWidth).present || field(kTileLength).present;
  // libtiff keeps strip and tile offsets in one field, the last read winning: a file with both
  // could pass this walk with one and be decoded with the other.
  if ((field(kStripOffsets).present || field(kStripBytes).present) &&
      (field(kTileOffsets).present || field(kTileBytes).present))
    return "both strip and tile locations";
  std::uint64_t chunks = 0;
  Tag offsets_tag = kStripOffsets, bytes_tag = kStripBytes;
  if (tiled) {
    const std::uint64_t tw = scalar(kTileWidth, 0), th = scalar(kTileLength, 0);
    if (tw == 0 || th == 0 || tw % 16 != 0 || th % 16 != 0)
      return fmt::format("TIFF tiles of {} x {} pixels (they must be multiples of 16)", tw, th);
    if (const std::string e = tile_problem(tw, th, width, height); !e.empty()) return e;
    chunks = ceil_div(width, tw) * ceil_div(height, th) * planes;
    offsets_tag = kTileOffsets;
    bytes_tag = kTileBytes;
  } else {
    const std::uint64_t rows = std::min(std::max<std::uint64_t>(scalar(kRowsPerStrip, height), 1), height);
    chunks = ceil_div(height, rows) * planes;
  }
  const Field &offsets = field(offsets_tag), &sizes = field(bytes_tag);
  const char* what = tiled ? "tile" : "strip";
  if (!offsets.present || !sizes.present) return fmt::format("the {} offsets or byte counts are missing", what);
  if (offsets.count < chunks || sizes.count < chunks)
    return fmt::format("the image needs {} {}s but the header locates {}", chunks, what,
                       std::min(offsets.count, sizes.count));
  if (offsets.type_size > 8 || sizes.type_size > 8) return fmt::format("the {} offsets are not integers", what);
  std::uint64_t total = 0;
  for (std::uint64_t i = 0; i < chunks; ++i) {
    const std::uint64_t at = value(offsets, i), n = value(sizes, i);
    if (at > b.size() || b.size() - at < n)
      return fmt::format("{} {} of {} ({} bytes at byte {}) runs past the end of the file ({} bytes; truncated?)", what,
                         i + 1, chunks, n, at, b.size());
    total += n;
  }
  // Strips or tiles that share bytes (thousands pointing at the same few) would each be decoded.
  if (total > b.size())
    return fmt::format("its {}s claim {} bytes in all, more than the file's {}", what, total, b.size());
  // The image data against what its compression can hold: uncompressed, every byte; PackBits at
  // most 64:1 (2 bytes for a run of 128); LZW about 2731:1 (12-bit codes for strings of at most
  // 4096 bytes); Deflate 1032:1 (zlib); JPEG one bit an 8 x 8 block (of a subsampled chroma
  // sample, at worst); others
  // (fax, ZSTD, LZMA, WebP) at most 65536:1.
  const std::uint64_t raw = width * height * samples * bits / 8;
  std::uint64_t ratio = 65536;
  switch (scalar(kCompression, 1)) {
    case 1: ratio = 1; break;
    case 32773: ratio = 64; break;
    case 5: ratio = 2731; break;
    case 8:
    case 32946: ratio = 1032; break;
    case 7: ratio = 2 * 64 * std::max<std::uint64_t>(bits, 8); break;  // x 2: chroma subsampling
    default: break;
  }
  if (ratio == 1 ? total < raw : total < raw / ratio)
    return fmt::format("the header claims {} x {} pixels ({} bytes of samples), which need at least {} bytes of "
                       "{} data, but its {}s hold {}",
                       width, height, raw, ratio == 1 ? raw : raw / ratio,
                       ratio == 1 ? "uncompressed" : "compressed", what, total);
  return {};
}

std::string image_structure_problem(ImageFormat format, std::string_view bytes, const ImageLimits& limits) {
  switch (format) {
    case ImageFormat::png: return png_structure_problem(bytes, limits);
    case ImageFormat::exr: return exr_header_problem(bytes, limits);
    case ImageFormat::jpeg: return jpeg_structure_problem(bytes, limits);
    case ImageFormat::tiff: return tiff_structure_problem(bytes, limits);
    case ImageFormat::hdr:
    case ImageFormat::pnm: return {};
  }
  return {};
}

Image coverage_for_encoding(const Image& alpha, ImageFormat format) {
  Image a = alpha;
  if (format == ImageFormat::exr) {
    a.channel_names = {"Y"};
    return a;
  }
  for (float& v : a.pixels) v = std::clamp(v, 0.f, 1.f);
  a.non_colour = true;  // linear codes, declared (gAMA 1.0, no sRGB chunk)
  return a;
}

Image depth_from_decoded(const DecodedImage& decoded, double scale_m, int width, int height, std::string_view origin) {
  if (decoded.format == ImageFormat::jpeg) throw Error(std::string(origin) + kJpegDepthRefusal);
  const Image& src = decoded.image;
  const bool coded =
      decoded.format == ImageFormat::png || decoded.format == ImageFormat::tiff || decoded.format == ImageFormat::pnm;
  if (std::abs(double(src.width) * height - double(src.height) * width) > double(std::max(width, height)))
    throw Error(fmt::format("{}: {}x{} has not the frame's aspect ({}x{})", origin, src.width, src.height, width,
                            height));
  // Upsampled by nearest neighbour, a map coarser than kMinDepthMapFraction of the frame a side would
  // put whole objects at one depth: refused rather than used for an occlusion it cannot give.
  const int min_w = (width + kMinDepthMapFraction - 1) / kMinDepthMapFraction;
  const int min_h = (height + kMinDepthMapFraction - 1) / kMinDepthMapFraction;
  if (src.width < min_w || src.height < min_h)
    throw Error(fmt::format("{}: {}x{} is too coarse for a {}x{} frame; a depth map needs at least 1/{} of the "
                            "frame a side ({}x{})",
                            origin, src.width, src.height, width, height, kMinDepthMapFraction, min_w, min_h));
  const double max_code = 65535;
  Image depth(width, height, 1);
  for (int y = 0; y < height; ++y) {
    const int sy = std::min(src.height - 1, int(std::int64_t(y) * src.height / height));
    for (int x = 0; x < width; ++x) {
      const int sx = std::min(src.width - 1, int(std::int64_t(x) * src.width / width));
      const float v = src.at(sx, sy, 0);
      double z = v;
      if (coded) {
        // The 16-bit code back: v is code / max for a file that declares linear codes, else the
        // code through the sRGB curve.
        const bool linear_png = decoded.linear && decoded.format == ImageFormat::png;
        z = std::round((linear_png ? double(v) : color::srgb_encode(double(v))) * max_code) * scale_m;
        if (z <= 0) z = std::numeric_limits<double>::infinity();  // code 0: no geometry
      }
      depth.at(x, y, 0) = float(z);
    }
  }
  return depth;
}

DecodedImage read_decoded(const ImageCodec& codec, std::string_view label, const fs::path& path,
                          const std::function<void(const std::string&)>& warn) {
  const std::string bytes = read_file(path, ImageLimits{}.max_file_bytes, label);
  const std::string origin = fmt::format("{} {}", label, path.string());
  auto decoded = codec.decode(bytes, origin, ImageLimits{});
  if (warn)
    for (const auto& w : decoded.warnings) warn(fmt::format("{}: {}", origin, w));
  return decoded;
}

}  // namespace hydrolux::io
