// PNG through libdeflate (src/io/png_codec.cpp): the fast reader gives the very floats OpenImageIO's
// reader (libpng) gives, over every filter type, 8 and 16 bits, grey and RGB; what it does not take
// (alpha, transparency, a bad checksum, a bad filter byte, too much or too little image data) goes
// to OpenImageIO, which reads it or names the fault as before.
#include <gtest/gtest.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/image_io.hpp"
#include "io/png_codec.hpp"

namespace hydrolux::io {
namespace {

// ---- PNG files built by hand: chunks with their CRC, image data as stored deflate blocks ----

std::uint32_t crc32(const std::string& bytes) {  // ISO 3309, as PNG uses it (bitwise)
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

std::string be32(std::uint32_t v) { return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

std::string chunk(const std::string& type, const std::string& data) {
  return be32(std::uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

// A zlib stream of stored (uncompressed) deflate blocks.
std::string zlib_stored(const std::string& raw) {
  std::string z = "\x78\x01";
  std::size_t at = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
    const bool last = at + n == raw.size();
    z += char(last ? 1 : 0);
    z += {char(n & 0xff), char(n >> 8), char(~n & 0xff), char((~n >> 8) & 0xff)};
    z += raw.substr(at, n);
    at += n;
  } while (at < raw.size());
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
  return z + be32(b << 16 | a);
}

std::string png_file(int w, int h, int bits, int colour, const std::string& raw_rows, const std::string& extra = {}) {
  const std::string ihdr = be32(std::uint32_t(w)) + be32(std::uint32_t(h)) + char(bits) + char(colour) + std::string(3, '\0');
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + extra + chunk("IDAT", zlib_stored(raw_rows)) +
         chunk("IEND", "");
}

// ---- the reference: OpenImageIO's reader, the codes' floats through the sRGB curve ----

std::vector<float> libpng_floats(const std::string& png) {
  OIIO::Filesystem::IOMemReader proxy(const_cast<char*>(png.data()), png.size());
  OIIO::ImageSpec config;
  void* proxy_ptr = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  auto in = OIIO::ImageInput::create("png");
  OIIO::ImageSpec spec;
  EXPECT_TRUE(in->open("x.png", spec, config)) << in->geterror();
  std::vector<float> px(spec.image_pixels() * std::size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) << in->geterror();
  for (float& v : px) v = color::srgb_decode(v);
  return px;
}

std::string oiio_png(const std::vector<std::uint16_t>& codes, int w, int h, int c, int bits) {
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput proxy(buffer);
  auto out = OIIO::ImageOutput::create("png");
  const OIIO::TypeDesc type = bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16;
  OIIO::ImageSpec spec(w, h, c, type);
  void* proxy_ptr = &proxy;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  std::vector<std::uint8_t> c8(codes.begin(), codes.end());
  const void* data = bits == 8 ? static_cast<const void*>(c8.data()) : static_cast<const void*>(codes.data());
  EXPECT_TRUE(out->open("x.png", spec) && out->write_image(type, data) && out->close());
  return std::string(buffer.begin(), buffer.end());
}

// Codes mixing smooth ramps, flat runs and noise, so that libpng's adaptive choice uses every filter.
std::vector<std::uint16_t> mixed_codes(int w, int h, int c, int bits) {
  std::mt19937 rng(11);
  const int max = bits == 8 ? 255 : 65535;
  std::uniform_int_distribution<int> noise(0, max);
  std::vector<std::uint16_t> v(std::size_t(w) * std::size_t(h) * std::size_t(c));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) {
        const int band = y / 8 % 4;
        const int value = band == 0 ? (x * 7 + y * 3 + k * 50) % (max + 1)
                          : band == 1 ? (y * 13 + k) % (max + 1)
                          : band == 2 ? noise(rng)
                                      : (x * x / 3 + y) % (max + 1);
        v[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * std::size_t(c) + std::size_t(k)] = std::uint16_t(value);
      }
  return v;
}

// Samples (PNG order, big-endian) filtered row by row with filter y % 5 (None, Sub, Up, Average,
// Paeth: the PNG specification's definitions), each row led by its filter byte.
std::string filtered_rows(const std::vector<std::uint8_t>& s, std::size_t row, std::size_t bpp) {
  std::string out;
  const std::size_t h = s.size() / row;
  for (std::size_t y = 0; y < h; ++y) {
    const int type = int(y % 5);
    out += char(type);
    for (std::size_t i = 0; i < row; ++i) {
      const int x = s[y * row + i];
      const int a = i >= bpp ? s[y * row + i - bpp] : 0, b = y > 0 ? s[(y - 1) * row + i] : 0;
      const int c = i >= bpp && y > 0 ? s[(y - 1) * row + i - bpp] : 0;
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      const int predictor = type == 0   ? 0
                            : type == 1 ? a
                            : type == 2 ? b
                            : type == 3 ? (a + b) / 2
                                        : (pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
      out += char(std::uint8_t(x - predictor));
    }
  }
  return out;
}

std::vector<std::uint8_t> sample_bytes(const std::vector<std::uint16_t>& codes, int bits) {
  std::vector<std::uint8_t> b;
  for (std::uint16_t v : codes) {
    if (bits == 16) b.push_back(std::uint8_t(v >> 8));
    b.push_back(std::uint8_t(v));
  }
  return b;
}

bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// PNGs libpng wrote with its adaptive filters (grey and RGB, 8 and 16 bits): the fast reader takes
// them, and decode_image gives libpng's codes through the curve, bit for bit, with channel names.
TEST(PngFastReader, SameFloatsAsLibpng) {
  for (int bits : {8, 16})
    for (int c : {1, 3}) {
      const int w = 61, h = 64;
      const std::string file = oiio_png(mixed_codes(w, h, c, bits), w, h, c, bits);
      const auto header = png::plain_header(file);
      ASSERT_TRUE(header) << bits << " bits, " << c << " channels";
      EXPECT_EQ(header->width, w);
      EXPECT_EQ(header->height, h);
      EXPECT_EQ(header->channels, c);
      EXPECT_EQ(header->bits, bits);
      std::vector<std::uint8_t> samples;
      EXPECT_TRUE(png::read_samples(file, *header, samples));
      const DecodedImage d = decode_image(file, "x.png");
      EXPECT_TRUE(same_floats(d.image.pixels, libpng_floats(file))) << bits << " bits, " << c << " channels";
      EXPECT_EQ(d.channel_names, c == 3 ? std::vector<std::string>({"R", "G", "B"}) : std::vector<std::string>({"Y"}));
      EXPECT_TRUE(d.warnings.empty());
    }
}

// Every filter type, 8 and 16 bits, grey and RGB, in files built here (stored deflate blocks): the
// fast reader's unfiltering gives libpng's floats.
TEST(PngFastReader, EveryFilterType) {
  for (int bits : {8, 16})
    for (int c : {1, 3}) {
      const int w = 23, h = 20;
      const auto codes = mixed_codes(w, h, c, bits);
      const std::size_t bpp = std::size_t(c * bits / 8);
      const std::string file =
          png_file(w, h, bits, c == 3 ? 2 : 0, filtered_rows(sample_bytes(codes, bits), bpp * std::size_t(w), bpp));
      ASSERT_TRUE(png::plain_header(file));
      std::vector<std::uint8_t> samples;
      ASSERT_TRUE(png::read_samples(file, *png::plain_header(file), samples));
      EXPECT_EQ(samples, sample_bytes(codes, bits));
      EXPECT_TRUE(same_floats(decode_image(file, "x.png").image.pixels, libpng_floats(file))) << bits << " bits, " << c;
    }
}

// hydrolux's own PNGs at the fast, the default and the small levels come back as the same floats
// through the fast reader and through libpng.
TEST(PngFastReader, ReadsWhatTheWriterWrites) {
  Image img(67, 41, 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& v : img.pixels) v = u(rng);
  for (int bits : {8, 16})
    for (int level : {0, 1, 6, 9}) {
      const std::string file = encode_image(img, ImageFormat::png, {bits, level});
      ASSERT_TRUE(png::plain_header(file));
      EXPECT_TRUE(same_floats(decode_image(file, "x.png").image.pixels, libpng_floats(file))) << bits << " " << level;
    }
}

// What the fast reader leaves to libpng: alpha and transparency (libpng adds or associates alpha),
// palettes, low bit depths and Adam7 (not the plain case); a bad CRC, a bad filter byte, image data
// too long or too short (read_samples refuses; libpng then reads or names the fault as before).
TEST(PngFastReader, LeavesTheRestToLibpng) {
  const std::string rows = std::string(1, '\0') + "abcdef" + std::string(1, '\0') + "ghijkl";  // 2 x 2 RGB, 8 bits
  const std::string good = png_file(2, 2, 8, 2, rows);
  ASSERT_TRUE(png::plain_header(good));
  std::vector<std::uint8_t> samples;
  EXPECT_TRUE(png::read_samples(good, *png::plain_header(good), samples));
  EXPECT_FALSE(png::plain_header(png_file(2, 2, 8, 6, rows)));                        // RGBA
  EXPECT_FALSE(png::plain_header(png_file(2, 2, 8, 4, rows)));                        // grey + alpha
  EXPECT_FALSE(png::plain_header(png_file(2, 2, 4, 0, rows)));                        // 4-bit grey
  EXPECT_FALSE(png::plain_header(png_file(2, 2, 8, 3, rows, chunk("PLTE", "abc"))));  // palette
  EXPECT_FALSE(png::plain_header(png_file(2, 2, 8, 2, rows, chunk("tRNS", "\0\1\0\2\0\3"))));
  std::string adam7 = good;
  adam7[8 + 8 + 12] = 1;  // the interlace byte (the CRC is left wrong: plain_header does not look)
  EXPECT_FALSE(png::plain_header(adam7));

  const auto refused = [&](const std::string& file) {
    std::vector<std::uint8_t> s;
    const auto h = png::plain_header(file);
    return h && !png::read_samples(file, *h, s);
  };
  std::string bad_crc = good;
  bad_crc[bad_crc.size() - 12 - 1] ^= 1;  // the IDAT chunk's CRC, last byte
  EXPECT_TRUE(refused(bad_crc));
  EXPECT_THROW((void)decode_image(bad_crc, "x.png"), IoError);  // libpng: "IDAT: CRC error"
  std::string bad_filter = rows;
  bad_filter[7] = 5;
  EXPECT_TRUE(refused(png_file(2, 2, 8, 2, bad_filter)));
  EXPECT_THROW((void)decode_image(png_file(2, 2, 8, 2, bad_filter), "x.png"), IoError);
  const std::string long_rows = rows + std::string(1, '\0') + "mnopqr";
  EXPECT_TRUE(refused(png_file(2, 2, 8, 2, long_rows)));
  EXPECT_TRUE(refused(png_file(2, 3, 8, 2, rows)));  // one row short
  EXPECT_THROW((void)decode_image(png_file(2, 3, 8, 2, rows), "x.png"), IoError);
  // Too much data: libpng reads the two rows and says so in a warning, as before the fast reader.
  const DecodedImage extra = decode_image(png_file(2, 2, 8, 2, long_rows), "x.png");
  EXPECT_EQ(extra.image.width, 2);
  EXPECT_TRUE(same_floats(extra.image.pixels, decode_image(good, "x.png").image.pixels));
}

// Data that is not colour (coverage masks: Image::non_colour) is written as linear codes with gAMA
// 1.0 and no sRGB chunk, and every reader takes a PNG that says so as code / max: the fast reader
// (grey, RGB) and OpenImageIO's (grey + alpha, RGBA) alike; an sRGB file, or one whose sRGB chunk
// overrides a gAMA of 1.0, still through the curve (issue 37: a mask's 0.17 read back as 0.02).
TEST(PngLinear, MasksReadBackAsWritten) {
  Image alpha(64, 8, 1);
  for (std::size_t i = 0; i < alpha.pixels.size(); ++i) alpha.pixels[i] = float(i) / float(alpha.pixels.size() - 1);
  alpha.pixels[5] = 0.17f;
  for (const int bits : {8, 16}) {
    const std::string file = encode_image(coverage_for_encoding(alpha, ImageFormat::png), ImageFormat::png, {bits, 6});
    EXPECT_EQ(file.find("sRGB"), std::string::npos);
    EXPECT_NE(file.find(std::string("gAMA\x00\x01\x86\xa0", 8)), std::string::npos);
    EXPECT_TRUE(png::declares_linear(file));
    const auto h = png::plain_header(file);
    ASSERT_TRUE(h && h->linear);
    const DecodedImage d = decode_image(file, "mask.png");
    EXPECT_TRUE(d.linear);
    const double step = bits == 8 ? 255.0 : 65535.0;
    for (std::size_t i = 0; i < alpha.pixels.size(); ++i)
      ASSERT_NEAR(d.image.pixels[i], alpha.pixels[i], 0.5 / step + 1e-7) << bits << " bits, value " << i;
  }
  // Three channels (the fast reader) and a file the fast reader leaves to OpenImageIO's (more image
  // data than the rows): the same linear reading.
  Image data(16, 4, 3);
  for (std::size_t i = 0; i < data.pixels.size(); ++i) data.pixels[i] = float(i % 97) / 96.0f;
  data.non_colour = true;
  const DecodedImage rgb = decode_image(encode_image(data, ImageFormat::png, {16, 6}), "data.png");
  EXPECT_TRUE(rgb.linear);
  for (std::size_t i = 0; i < data.pixels.size(); ++i)
    ASSERT_NEAR(rgb.image.pixels[i], data.pixels[i], 0.5 / 65535 + 1e-7) << "value " << i;
  // A colour image still goes through the curve, and says so.
  Image colour(4, 4, 3);
  for (std::size_t i = 0; i < colour.pixels.size(); ++i) colour.pixels[i] = float(i) / 47.0f;
  const std::string srgb = encode_image(colour, ImageFormat::png, {16, 6});
  EXPECT_NE(srgb.find("sRGB"), std::string::npos);
  EXPECT_FALSE(png::declares_linear(srgb));
  const DecodedImage back = decode_image(srgb, "colour.png");
  EXPECT_FALSE(back.linear);
  for (std::size_t i = 0; i < colour.pixels.size(); ++i) EXPECT_NEAR(back.image.pixels[i], colour.pixels[i], 2e-5);
  // Files from elsewhere: gAMA 1.0 alone is linear; with an sRGB chunk (which takes precedence) or
  // another gamma, the curve.
  const std::string rows = std::string("\0", 1) + "\x2b\x80";  // one row of 2 grey pixels: 43, 128
  const std::string gama1 = chunk("gAMA", be32(100000)), gama045 = chunk("gAMA", be32(45455));
  const std::string srgb_chunk = chunk("sRGB", std::string(1, '\0'));
  const DecodedImage lin = decode_image(png_file(2, 1, 8, 0, rows, gama1), "x.png");
  EXPECT_TRUE(lin.linear);
  EXPECT_FLOAT_EQ(lin.image.pixels[0], 43.0f / 255.0f);
  const std::string too_long = png_file(2, 1, 8, 0, rows + std::string(1, '\0') + "\x01\x02", gama1);
  std::vector<std::uint8_t> samples;
  EXPECT_FALSE(png::read_samples(too_long, *png::plain_header(too_long), samples));  // to OpenImageIO
  const DecodedImage oiio = decode_image(too_long, "x.png");
  EXPECT_TRUE(oiio.linear);
  EXPECT_FLOAT_EQ(oiio.image.pixels[0], 43.0f / 255.0f);
  EXPECT_FLOAT_EQ(oiio.image.pixels[1], 128.0f / 255.0f);
  for (const std::string& extra : {gama045, srgb_chunk + gama1, gama1 + srgb_chunk, std::string()}) {
    const DecodedImage d = decode_image(png_file(2, 1, 8, 0, rows, extra), "x.png");
    EXPECT_FALSE(d.linear);
    EXPECT_FLOAT_EQ(d.image.pixels[0], float(color::srgb_decode(43.0f / 255.0f)));
  }
}

}  // namespace
}  // namespace hydrolux::io
