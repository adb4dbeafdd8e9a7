#pragma once
// Hostile image files for tests: tiny files whose headers claim huge sizes, truncated and corrupt
// files. Built byte by byte (the PNG chunk CRC is computed here), so no test depends on a codec to
// make them. Header-only.
#include <array>
#include <cstdint>
#include <string>

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

}  // namespace hydrolux::testing
