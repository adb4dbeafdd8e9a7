#pragma once
// Hostile image files for tests: tiny files whose headers claim huge sizes, truncated and corrupt
// files. Built byte by byte (the PNG chunk CRC is computed here), so no test depends on a codec to
// make them. Header-only.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hydrolux::testing {

inline std::uint32_t crc32(const std::string& bytes) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) c = table[(c ^ b) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

inline std::string be32(std::uint32_t v) {
  return {char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
}

inline std::string png_chunk(const std::string& type, const std::string& data) {
  return be32(std::uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

// A PNG whose header claims width x height 8-bit RGB pixels, with one IDAT holding a stored
// (uncompressed) zlib block of `idat_payload` zero bytes: valid framing, far too little data.
inline std::string png_claiming(std::uint32_t width, std::uint32_t height, std::uint16_t idat_payload = 16) {
  const std::string sig = "\x89PNG\r\n\x1a\n";
  std::string ihdr = be32(width) + be32(height);
  ihdr += std::string{char(8), char(2), char(0), char(0), char(0)};  // 8 bits, RGB, no interlace
  std::string z = "\x78\x01";                                        // zlib header
  z += char(1);                                                      // final stored block
  z += char(idat_payload & 0xff);
  z += char(idat_payload >> 8);
  z += char(~idat_payload & 0xff);
  z += char((~idat_payload >> 8) & 0xff);
  z += std::string(idat_payload, '\0');
  z += be32(1);  // a (wrong) adler32: the data runs out first anyway
  return sig + png_chunk("IHDR", ihdr) + png_chunk("IDAT", z) + png_chunk("IEND", "");
}

// A Radiance HDR whose header claims width x height pixels, followed by a few flat RGBE pixels.
inline std::string hdr_claiming(std::uint32_t width, std::uint32_t height) {
  return "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " + std::to_string(width) +
         "\n" + std::string(40, '\x80');
}

// A binary PPM whose header claims width x height pixels, with a few bytes of data.
inline std::string ppm_claiming(std::uint32_t width, std::uint32_t height) {
  return "P6\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n" + std::string(30, '\x7f');
}

// A progressive JPEG (SOF2) of width x height 8-bit grey pixels made of `scans` empty DC scans,
// ending with EOI unless `truncated`: the marker structure of a file that makes a decoder pass
// over the whole image once a scan.
inline std::string jpeg_with_scans(std::uint16_t width, std::uint16_t height, int scans, bool truncated = false) {
  const auto be16 = [](unsigned v) { return std::string{char(v >> 8), char(v & 0xff)}; };
  std::string j = "\xff\xd8";
  j += "\xff\xc2" + be16(11) + char(8) + be16(height) + be16(width) + char(1) + char(1) + char(0x11) + char(0);
  for (int s = 0; s < scans; ++s)
    j += "\xff\xda" + be16(8) + char(1) + char(1) + char(0) + char(0) + char(0) + char(0) + std::string(4, '\0');
  if (!truncated) j += "\xff\xd9";
  return j;
}

// A little-endian TIFF of width x height 8-bit grey pixels, in one strip or (tile_size > 0) in
// tiles of tile_size x tile_size, with `data_bytes` zero bytes of image data while the strip or
// tile byte counts claim `claimed_bytes` each (equal for a valid file): one image directory.
inline std::string tiff_claiming(std::uint32_t width, std::uint32_t height, std::uint32_t tile_size,
                                 std::uint32_t data_bytes, std::uint32_t claimed_bytes) {
  const auto le16 = [](unsigned v) { return std::string{char(v & 0xff), char(v >> 8)}; };
  const auto le32 = [](std::uint32_t v) {
    return std::string{char(v & 0xff), char((v >> 8) & 0xff), char((v >> 16) & 0xff), char(v >> 24)};
  };
  struct Entry {
    unsigned tag, type;
    std::uint32_t count, value;
  };
  const std::uint32_t tiles_across = tile_size ? (width + tile_size - 1) / tile_size : 1;
  const std::uint32_t tiles_down = tile_size ? (height + tile_size - 1) / tile_size : 1;
  const std::uint32_t chunks = tiles_across * tiles_down;
  std::vector<Entry> e = {{256, 4, 1, width}, {257, 4, 1, height}, {258, 3, 1, 8}, {259, 3, 1, 1}, {262, 3, 1, 1}};
  const std::uint32_t entries = 5 + 3 + (tile_size ? 3 : 1);
  const std::uint32_t ifd_end = 8 + 2 + 12 * entries + 4;
  // With several chunks, their offsets and byte counts are arrays after the directory.
  const std::uint32_t arrays = chunks > 1 ? ifd_end : 0, data = ifd_end + (chunks > 1 ? 8 * chunks : 0);
  const std::uint32_t offsets_value = chunks > 1 ? arrays : data, counts_value = chunks > 1 ? arrays + 4 * chunks : claimed_bytes;
  if (tile_size) {
    e.push_back({277, 3, 1, 1});
    e.push_back({284, 3, 1, 1});
    e.push_back({322, 4, 1, tile_size});
    e.push_back({323, 4, 1, tile_size});
    e.push_back({324, 4, chunks, offsets_value});
    e.push_back({325, 4, chunks, counts_value});
  } else {
    e.insert(e.end(), {{273, 4, 1, offsets_value}, {277, 3, 1, 1}, {278, 4, 1, height}, {279, 4, 1, counts_value}});
  }
  std::string t = "II" + le16(42) + le32(8) + le16(unsigned(e.size()));
  for (const auto& x : e)
    t += le16(x.tag) + le16(x.type) + le32(x.count) + (x.type == 3 && x.count == 1 ? le16(x.value) + le16(0) : le32(x.value));
  t += le32(0);  // no next directory
  if (chunks > 1) {
    const std::uint32_t each = data_bytes / chunks;
    for (std::uint32_t k = 0; k < chunks; ++k) t += le32(data + k * each);
    for (std::uint32_t k = 0; k < chunks; ++k) t += le32(claimed_bytes);
  }
  return t + std::string(data_bytes, '\0');
}

// A little-endian TIFF from raw directory entries {tag, type (3 SHORT, 4 LONG), count, value},
// written in the order given (repeats allowed), followed by `data_bytes` zero bytes starting at
// the offset tiff_data_offset(entries.size()) returns.
inline std::uint32_t tiff_data_offset(std::size_t entries) { return std::uint32_t(8 + 2 + 12 * entries + 4); }
inline std::string tiff_from_entries(const std::vector<std::array<std::uint32_t, 4>>& entries, std::uint32_t data_bytes) {
  const auto le16 = [](unsigned v) { return std::string{char(v & 0xff), char(v >> 8)}; };
  const auto le32 = [](std::uint32_t v) {
    return std::string{char(v & 0xff), char((v >> 8) & 0xff), char((v >> 16) & 0xff), char(v >> 24)};
  };
  std::string t = "II" + le16(42) + le32(8) + le16(unsigned(entries.size()));
  for (const auto& [tag, type, count, value] : entries)
    t += le16(tag) + le16(type) + le32(count) + (type == 3 && count == 1 ? le16(value) + le16(0) : le32(value));
  return t + le32(0) + std::string(data_bytes, '\0');
}

}  // namespace hydrolux::testing
