// Image files: EXR round trip, PNG through the sRGB curve, errors; headers never trusted (limits and
// file-size bounds checked before any pixel memory), codec messages captured into one line, and the
// same image encoded to the same bytes.
#include <gtest/gtest.h>

#include <array>

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"
#include "support/asan.hpp"
#include "support/crafted_images.hpp"
#include "support/sandbox.hpp"


namespace hydrolux::io {
namespace {

namespace fs = std::filesystem;

class ImageIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hydrolux_test_io_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::size_t file_count() const {
    return std::size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

Image gradient(int w, int h, int c) {
  Image img(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) img.at(x, y, k) = float(x + w * y + k) / float(w * h + c);
  return img;
}

// The sRGB curve (IEC 61966-2-1): 0.5 linear encodes to 0.7353569; the two pieces meet at
// 0.0031308 -> 0.04045; decode inverts encode.
TEST(Srgb, KnownValuesAndInverse) {
  EXPECT_NEAR(color::srgb_encode(0.5), 0.7353569, 1e-7);
  EXPECT_NEAR(color::srgb_encode(0.0031308), 0.04045, 1e-6);
  EXPECT_NEAR(color::srgb_encode(0.0031308 * (1 + 1e-9)), 0.04045, 1e-6);  // continuous
  EXPECT_EQ(color::srgb_encode(-1.0), 0.0);
  EXPECT_EQ(color::srgb_encode(2.0), 1.0);
  for (int i = 0; i <= 1000; ++i) EXPECT_NEAR(color::srgb_decode(color::srgb_encode(i / 1000.0)), i / 1000.0, 1e-12);
}

TEST_F(ImageIo, ExrRoundTripIsExact) {
  Image img = gradient(17, 9, 3);
  img.at(3, 4, 1) = 1234.5f;  // HDR values survive
  write_image(dir_ / "a.exr", img);
  const Image back = read_image(dir_ / "a.exr");
  ASSERT_EQ(back.width, 17);
  ASSERT_EQ(back.height, 9);
  ASSERT_EQ(back.channels, 3);
  EXPECT_EQ(back.pixels, img.pixels);
}

// 8-bit PNG: values are stored through the sRGB curve, so the round trip error is at most half a
// code value in encoded space (0.5/255), plus float rounding.
TEST_F(ImageIo, PngStoresTheSrgbCurve) {
  for (int bits : {8, 16}) {
    const Image img = gradient(32, 8, 3);
    const fs::path p = dir_ / ("b" + std::to_string(bits) + ".png");
    write_image(p, img, {bits});
    const Image back = read_image(p);
    ASSERT_EQ(back.pixels.size(), img.pixels.size());
    const double half_code = 0.5 / (bits == 8 ? 255.0 : 65535.0);
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
      EXPECT_NEAR(color::srgb_encode(double(back.pixels[i])), color::srgb_encode(double(img.pixels[i])),
                  half_code + 1e-6);
  }
  // Linear 0.5 is stored as code round(0.7353569 * 255) = 188, which reads back as 188/255 decoded.
  Image mid(1, 1, 1);
  mid.pixels[0] = 0.5f;
  write_image(dir_ / "mid.png", mid);
  EXPECT_NEAR(read_image(dir_ / "mid.png").pixels[0], color::srgb_decode(188.0 / 255.0), 1e-6);
}

TEST_F(ImageIo, ErrorsNameTheFile) {
  try {
    (void)read_image(dir_ / "missing.exr");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos);
  }
  std::ofstream(dir_ / "junk.png") << "this is not a png";
  EXPECT_THROW((void)read_image(dir_ / "junk.png"), IoError);
  EXPECT_THROW(write_image(dir_ / "x.bmpx", gradient(2, 2, 3)), IoError);
  EXPECT_THROW(write_image(dir_ / "x.png", gradient(2, 2, 3), {12}), IoError);
  Image bad(2, 2, 3);
  bad.pixels.pop_back();
  EXPECT_THROW(write_image(dir_ / "bad.exr", bad), IoError);
  EXPECT_FALSE(fs::exists(dir_ / "x.bmpx"));
  EXPECT_FALSE(fs::exists(dir_ / "bad.exr"));
}

// A seed file of the image fuzzer (fuzz/corpus/image): real files of every format and layout, and
// the hostile inputs fuzzing found.
std::string seed(const std::string& name) {
  std::ifstream in(fs::path(HYDROLUX_SOURCE_DIR) / "fuzz" / "corpus" / "image" / name, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const IoError& e) {
    return e.what();
  }
  return "no IoError";
}

// A header claiming more than the limits (or more than the file can hold) is refused before any
// pixel memory is allocated: with a 2 GiB address-space limit in a child, decoding a 100 000 x
// 100 000 PNG (30 GB of pixels) must end in IoError, not bad_alloc. The limit is set in a child
// without AddressSanitizer, whose shadow memory needs far more address space.
TEST_F(ImageIo, HugeHeadersAreRefusedBeforeAllocating) {
  const std::string png = testing::png_claiming(100000, 100000);
  const std::string m = message_of([&] { (void)decode_image(png, "--image huge.png"); });
  EXPECT_NE(m.find("--image huge.png: malformed, truncated or oversized PNG file: the header claims 100000 x 100000 pixels"), std::string::npos) << m;
  EXPECT_NE(m.find("limit"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos);
  const std::string hdr = testing::hdr_claiming(200000, 200000);
  EXPECT_NE(message_of([&] { (void)decode_image(hdr, "env.hdr"); }).find("claims 200000 x 200000"), std::string::npos);
#if !HYDROLUX_TEST_ASAN
  const int code = testing::run_in_child([&] {
    const rlimit lim{std::uint64_t(2) << 30, std::uint64_t(2) << 30};
    if (::setrlimit(RLIMIT_AS, &lim) != 0) return testing::kChildCannotSetUp;
    try {
      (void)decode_image(png, "huge.png");
    } catch (const IoError&) {
      return 0;
    } catch (const std::bad_alloc&) {
      return 2;
    }
    return 1;
  });
  EXPECT_EQ(code, 0);
#endif
}

// Within the limits, a header claiming more pixels than the file's bytes can encode at the format's
// best compression is refused too: PNG (deflate at most 1032:1), HDR (run-length), binary PPM (none).
TEST_F(ImageIo, HeadersAreCheckedAgainstTheFileSize) {
  const std::string png = testing::png_claiming(10000, 10000);  // 300 MB of pixels in ~100 bytes
  std::string m = message_of([&] { (void)decode_image(png, "a.png"); });
  EXPECT_NE(m.find("need at least 290707 bytes of compressed image data, but the IDAT chunks hold 27"),
            std::string::npos)
      << m;
  m = message_of([&] { (void)decode_image(testing::hdr_claiming(10000, 10000), "a.hdr"); });
  EXPECT_NE(m.find("bytes of Radiance HDR data"), std::string::npos) << m;
  m = message_of([&] { (void)decode_image(testing::ppm_claiming(10000, 10000), "a.ppm"); });
  EXPECT_NE(m.find("needs at least 300000000 bytes of PNM data"), std::string::npos) << m;
  // Real files meet the bounds: a noise image (incompressible) and a flat one (compresses best).
  for (const bool flat : {false, true}) {
    Image img(300, 200, 3);
    std::uint32_t state = 12345;
    for (auto& v : img.pixels) v = flat ? 0.25f : float((state = state * 1664525u + 1013904223u) >> 8) / 16777216.f;
    const std::string bytes = encode_image(img, ImageFormat::png);
    EXPECT_GE(bytes.size(), min_encoded_bytes(ImageFormat::png, 300, 200, 3, 8));
    EXPECT_EQ(decode_image(bytes, "ok.png").image.width, 300);
  }
}

// Truncated and corrupt files fail with one line naming the file; what libpng prints on stderr is
// captured into that line instead of reaching the terminal.
TEST_F(ImageIo, TruncatedFilesFailInOneLineWithCodecMessagesCaptured) {
  Image img(64, 64, 3);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(i % 97) / 97.f;
  const std::string png = encode_image(img, ImageFormat::png);
  const std::string exr = encode_image(img, ImageFormat::exr);
  // Point our own stderr at a file, as a terminal would show it.
  const fs::path err_file = dir_ / "stderr.txt";
  std::fflush(stderr);
  const int saved = ::dup(2);
  FILE* f = std::fopen(err_file.c_str(), "w");
  ::dup2(::fileno(f), 2);
  std::vector<std::string> messages;
  for (const auto& [bytes, name] : {std::pair{png.substr(0, png.size() / 2), "half.png"},
                                    std::pair{png.substr(0, 60), "header-only.png"},
                                    std::pair{exr.substr(0, exr.size() / 2), "half.exr"},
                                    std::pair{std::string("\x89PNG\r\n\x1a\n") + "garbage", "garbage.png"},
                                    std::pair{testing::png_claiming(64, 64, 16), "short-data.png"},
                                    std::pair{std::string("P3\n2 2\n255\n") + "x x x x x x x x x x x x ", "letters.ppm"}})
    messages.push_back(message_of([&] { (void)decode_image(bytes, name); }));
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  std::fclose(f);
  std::ifstream in(err_file);
  std::stringstream printed;
  printed << in.rdbuf();
  EXPECT_EQ(printed.str(), "") << "a codec printed on stderr";
  for (const auto& m : messages) {
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_TRUE(m.find("cannot read the") != std::string::npos || m.find("malformed, truncated or oversized") != std::string::npos)
        << m;
  }
  // A truncated PNG is caught by its chunk structure, before the codec; a whole one whose image
  // data run short fails in libpng, whose own "libpng error" line is captured into the message.
  EXPECT_NE(messages[0].find("half.png: malformed, truncated or oversized PNG file: the file ends inside the IDAT chunk"),
            std::string::npos)
      << messages[0];
  EXPECT_NE(messages[4].find("short-data.png: cannot read the PNG data: "), std::string::npos)
      << messages[4];
  EXPECT_NE(message_of([] { (void)decode_image("hello, world", "t.png"); }).find("not an image hydrolux reads"),
            std::string::npos);
}

// Every format hydrolux reads, through its read path: the fuzzers' seed files (fuzz/corpus/image)
// of each format and layout decode, the hostile ones are refused in one line.
TEST(ImageFormats, EveryFormatAndLayoutDecodes) {
  for (const char* good : {"drop.png", "drop.exr", "tiled.exr", "multipart.exr", "drop.hdr", "drop.ppm", "ascii.ppm",
                           "gray.pgm", "tiny.pfm", "drop.jpg", "progressive.jpg", "drop.tif", "tiled.tif", "bigtiff.tif", "palette.png", "mipmap.exr"}) {
    try {
      const auto d = decode_image(seed(good), good);
      EXPECT_GT(d.image.width, 0) << good;
      EXPECT_EQ(d.image.pixels.size(), std::size_t(d.image.width) * d.image.height * d.image.channels) << good;
    } catch (const IoError& e) {
      ADD_FAILURE() << good << ": " << e.what();
    }
  }
  // exr-bad-pixel-type.exr made OpenImageIO 2.4 abort (an assertion on the channel pixel type).
  for (const char* bad : {"huge.png", "truncated.png", "exr-huge-string-attribute.exr", "exr-bad-pixel-type.exr"})
    EXPECT_THROW((void)decode_image(seed(bad), bad), IoError) << bad;
  // Made OpenImageIO 2.4 read past a JPEG metadata marker (found by fuzz_image; under
  // AddressSanitizer this test fails if its metadata reach the codec again).
  try {
    (void)decode_image(seed("jpeg-metadata-overflow.jpg"), "overflow.jpg");
  } catch (const IoError&) {
  }
}

// OpenEXR trusts its header: a string attribute declaring 1.8 GB in a 1 kB file (found by
// fuzz_image) made it allocate and clear 1.8 GB for 4 s before failing; a data window far larger
// than the file sizes its chunk offset table. Both are refused from hydrolux's own walk of the
// header, before OpenEXR reads it.
TEST(ImageFormats, ExrHeadersAreWalkedBeforeOpenExrTrustsThem) {
  EXPECT_NE(message_of([&] { (void)decode_image(seed("exr-huge-string-attribute.exr"), "fuzz.exr"); })
                .find("oversized OpenEXR file: attribute 'capDate' claims 1845493859 bytes"),
            std::string::npos);
  // A valid 16 x 8 EXR with its data window rewritten.
  Image img(16, 8, 3);
  const std::string exr = encode_image(img, ImageFormat::exr);
  EXPECT_EQ(exr_header_problem(exr, {}), "");
  const auto with_window = [&](std::int32_t xmax, std::int32_t ymax) {
    std::string e = exr;
    const std::string key("dataWindow\0box2i\0", 17);
    const auto at = e.find(key) + key.size() + 4;  // after the attribute's size
    for (int k = 0; k < 4; ++k) e[at + 8 + k] = char((std::uint32_t(xmax) >> (8 * k)) & 0xff);
    for (int k = 0; k < 4; ++k) e[at + 12 + k] = char((std::uint32_t(ymax) >> (8 * k)) & 0xff);
    return e;
  };
  EXPECT_NE(exr_header_problem(with_window(99999, 99999), {}).find("claims 100000 x 100000 pixels"), std::string::npos);
  EXPECT_NE(message_of([&] { (void)decode_image(with_window(15, 59999), "tall.exr"); })
                .find("the header asks for 3750 chunks, whose offset table alone needs 30000 bytes"),
            std::string::npos);
  EXPECT_NE(exr_header_problem(exr.substr(0, 40), {}).find("the file ends inside"), std::string::npos);

  // Tiles are bounded as TIFF's are: OpenEXR allocates a tile buffer for each thread slot, and a
  // 440-byte 1 x 1 file with 8192 x 8192 tiles took 1.15 GB (found in review).
  std::string tiled = seed("tiled.exr");
  EXPECT_EQ(exr_header_problem(tiled, {}), "");
  const std::string tiles_key("tiles\0tiledesc\0", 15);
  const auto tiles_at = tiled.find(tiles_key) + tiles_key.size() + 4;
  for (int k = 0; k < 8; ++k) tiled[tiles_at + k] = "\x00\x20\x00\x00\x00\x20\x00\x00"[k];  // 8192, 8192
  EXPECT_NE(exr_header_problem(tiled, {}).find("tiles of 8192 x 8192 pixels"), std::string::npos)
      << exr_header_problem(tiled, {});

  // A single-part file's offset table is sized from its data window, as OpenEXR sizes it: a stray
  // chunkCount attribute (which OpenEXR ignores there) cannot switch the offset check off.
  std::size_t end = 8;
  while (exr[end] != '\0') {                         // name, type, size, value
    end = exr.find('\0', end) + 1;
    end = exr.find('\0', end) + 1;
    std::uint32_t size = 0;
    for (int k = 0; k < 4; ++k) size |= std::uint32_t(static_cast<unsigned char>(exr[end + k])) << (8 * k);
    end += 4 + size;
  }
  std::string stray = exr.substr(0, end) + std::string("chunkCount\0int\0\x04\0\0\0\0\0\0\0", 24) + exr.substr(end);
  const std::size_t table = end + 24 + 1;
  stray.replace(table, 8, std::string("\0\0\0\0\0\0\xff\x7f", 8));  // zip: 16 lines a chunk, so one chunk
  EXPECT_NE(exr_header_problem(stray, {}).find("the offset table puts chunk 1 of 1 at byte"), std::string::npos)
      << exr_header_problem(stray, {});
}

// JPEG and TIFF are walked before their codecs too (the hostile files a review found): a
// progressive JPEG is decoded while OpenImageIO opens it, scan by scan over the whole image, so its
// size and scan count are checked first; a truncated JPEG was decoded grey with exit 0; a 1 x 1
// TIFF in 65536 x 65536 tiles made libtiff allocate a whole tile; a TIFF whose strips run past its
// end was accepted.
TEST(ImageFormats, JpegAndTiffStructuresAreWalkedBeforeTheirCodecs) {
  const ImageLimits limits;
  // Real files pass the walk (and decode: EveryFormatAndLayoutDecodes).
  const std::string jpg = seed("drop.jpg"), tif = seed("drop.tif");
  const std::string progressive = seed("progressive.jpg"), tiled = seed("tiled.tif");
  for (const auto* f : {&jpg, &progressive}) EXPECT_EQ(jpeg_structure_problem(*f, limits), "");
  for (const auto* f : {&tif, &tiled}) EXPECT_EQ(tiff_structure_problem(*f, limits), "");

  const auto refused = [](const std::string& bytes, const char* name, const char* why) {
    const std::string m = message_of([&] { (void)decode_image(bytes, name); });
    EXPECT_NE(m.find(why), std::string::npos) << name << ": " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
  };
  // JPEG: truncated anywhere, too many scans, a frame beyond the limits or the file's bytes.
  for (const std::size_t cut : {jpg.size() / 2, jpg.size() - 2, std::size_t(200)})
    refused(jpg.substr(0, cut), "cut.jpg", "(truncated)");
  refused(progressive.substr(0, progressive.size() * 3 / 4), "cut-progressive.jpg", "(truncated)");
  EXPECT_EQ(jpeg_structure_problem(testing::jpeg_with_scans(64, 64, 100), limits), "");
  refused(testing::jpeg_with_scans(64, 64, 101), "scans.jpg", "more than 100 scans");
  refused(testing::jpeg_with_scans(64, 64, 3, true), "noeoi.jpg", "the file ends inside the image data (truncated)");
  refused(testing::jpeg_with_scans(65535, 65535, 1), "huge.jpg", "the limit is 268435456 pixels");
  refused(testing::jpeg_with_scans(16000, 16000, 1), "big.jpg", "need at least 500000 bytes of JPEG data");
  // TIFF: the builder's valid files decode; each defect is refused by the walk.
  for (const std::uint32_t tile : {0u, 16u}) {
    const std::string ok = testing::tiff_claiming(40, 24, tile, tile ? 3 * 2 * 256 : 40 * 24, tile ? 256 : 40 * 24);
    EXPECT_EQ(tiff_structure_problem(ok, limits), "") << tile;
    EXPECT_EQ(decode_image(ok, "ok.tif").image.width, 40) << tile;
    refused(ok.substr(0, ok.size() - 100), "cut.tif", "runs past the end of the file");
  }
  refused(testing::tiff_claiming(1, 1, 65536, 1, 1), "tile-bomb.tif", "tiles of 65536 x 65536 pixels for an image of 1 x 1");
  refused(testing::tiff_claiming(100000, 1, 0, 10, 10), "wide.tif", "the limit is 65536 pixels a side");
  refused(testing::tiff_claiming(64, 64, 0, 64, 1u << 30), "claims.tif", "runs past the end of the file");
  refused(tif.substr(0, 6), "header.tif", "the file ends inside the TIFF header");
  // Tiles larger than a small image are common (OpenImageIO writes 64 x 64 tiles for a 40 x 40
  // image; COGs use 512 x 512): allowed up to 512 x 512.
  EXPECT_EQ(decode_image(testing::tiff_claiming(40, 40, 64, 64 * 64, 64 * 64), "small.tif").image.width, 40);

  // What a second review found. A repeated tag counts once, as libtiff keeps the first: a 1 x 1
  // image whose first TileWidth/TileLength say 16384 is a tile bomb whatever follows.
  using E = std::array<std::uint32_t, 4>;
  const std::vector<E> head = {{256, 4, 1, 1}, {257, 4, 1, 1}, {258, 3, 1, 8}, {259, 3, 1, 1}, {262, 3, 1, 1}, {277, 3, 1, 1}};
  auto dup = head;
  dup.insert(dup.end(), {E{322, 4, 1, 16384}, E{322, 4, 1, 16}, E{323, 4, 1, 16384}, E{323, 4, 1, 16}});
  dup.insert(dup.end(), {E{324, 4, 1, testing::tiff_data_offset(12)}, E{325, 4, 1, 256}});
  refused(testing::tiff_from_entries(dup, 256), "dup.tif", "tiles of 16384 x 16384 pixels for an image of 1 x 1");
  // Strip and tile locations together (libtiff keeps them in one field).
  auto both = head;
  both.insert(both.end(), {E{273, 4, 1, testing::tiff_data_offset(12)}, E{278, 4, 1, 1}, E{279, 4, 1, 1},
                           E{322, 4, 1, 16}, E{323, 4, 1, 16}, E{325, 4, 1, 1}});
  refused(testing::tiff_from_entries(both, 256), "both.tif", "both strip and tile locations");
  // 8192 x 8192 RGBA in one Deflate strip of 100 bytes (it decoded, mostly zeros, at 1.1 GB).
  const std::vector<E> deflate = {{256, 4, 1, 8192}, {257, 4, 1, 8192}, {258, 3, 1, 8}, {259, 3, 1, 8},
                                  {262, 3, 1, 2},    {273, 4, 1, testing::tiff_data_offset(9)}, {277, 3, 1, 4},
                                  {278, 4, 1, 8192}, {279, 4, 1, 100}};
  refused(testing::tiff_from_entries(deflate, 100), "deflate.tif",
          "need at least 260111 bytes of compressed data, but its strips hold 100");
  // 4096 uncompressed strips of one row, all pointing at the same 16 bytes.
  const std::uint32_t strips = 4096, arrays = testing::tiff_data_offset(9);
  std::vector<E> shared = {{256, 4, 1, 16}, {257, 4, 1, strips}, {258, 3, 1, 8}, {259, 3, 1, 1}, {262, 3, 1, 1},
                           {273, 4, strips, arrays}, {277, 3, 1, 1}, {278, 4, 1, 1}, {279, 4, strips, arrays + 4 * strips}};
  std::string shared_tif = testing::tiff_from_entries(shared, 0);
  const std::uint32_t data_at = std::uint32_t(shared_tif.size()) + 8 * strips;
  for (std::uint32_t k = 0; k < strips; ++k) shared_tif += std::string{char(data_at & 0xff), char(data_at >> 8 & 0xff), char(data_at >> 16), 0};
  for (std::uint32_t k = 0; k < strips; ++k) shared_tif += std::string{16, 0, 0, 0};
  shared_tif += std::string(16, '\0');
  refused(shared_tif, "shared.tif", "its strips claim 65536 bytes in all, more than the file's");

  // JPEG: stray bytes between segments are skipped (libjpeg warns and reads on); arithmetic
  // coding, which has no bytes-a-block bound (a 114-byte file decoded 16384 x 16384), is refused.
  std::string stray = jpg;
  stray.insert(20, std::string(2, '\0'));  // after the APP0 segment
  EXPECT_EQ(jpeg_structure_problem(stray, limits), "");
  // Metadata segments never reach OpenImageIO (fuzz_image found its JPEG reader overflowing a saved
  // marker while opening jpeg-metadata-overflow.jpg): the Exif APP1 of drop.jpg is dropped, the
  // scans and tables are kept.
  ASSERT_NE(jpg.find("Exif"), std::string::npos);
  const std::string bare = jpeg_without_metadata(jpg);
  EXPECT_EQ(bare.find("Exif"), std::string::npos);
  EXPECT_LT(bare.size() + 200, jpg.size());  // the Exif segment is 270 bytes
  const std::string plain = testing::jpeg_with_scans(64, 64, 3);  // no metadata: unchanged
  EXPECT_EQ(jpeg_without_metadata(plain), plain);
  EXPECT_EQ(jpeg_structure_problem(bare, limits), "");
  const auto scans = [](const std::string& j) {
    std::size_t n = 0;
    for (std::size_t at = j.find("\xff\xda"); at != std::string::npos; at = j.find("\xff\xda", at + 2)) ++n;
    return n;
  };
  const std::string bare_progressive = jpeg_without_metadata(progressive);
  EXPECT_EQ(scans(bare_progressive), 10u);  // every scan kept
  EXPECT_EQ(bare_progressive.substr(bare_progressive.size() - 2), "\xff\xd9");
  EXPECT_EQ(jpeg_structure_problem(bare_progressive, limits), "");
  std::string arithmetic = testing::jpeg_with_scans(64, 64, 1);
  arithmetic[3] = char(0xca);  // SOF2 -> SOF10
  refused(arithmetic, "arith.jpg", "arithmetic-coded JPEG is not supported");
}

TEST(ImageFormats, SniffedFromTheFirstBytes) {
  EXPECT_EQ(sniff_image_format("\x89PNG\r\n\x1a\nrest"), ImageFormat::png);
  EXPECT_EQ(sniff_image_format(std::string("\x76\x2f\x31\x01", 4)), ImageFormat::exr);
  EXPECT_EQ(sniff_image_format("#?RADIANCE\n"), ImageFormat::hdr);
  EXPECT_EQ(sniff_image_format("#?RGBE\n"), ImageFormat::hdr);
  EXPECT_EQ(sniff_image_format("P6\n1 1\n255\n"), ImageFormat::pnm);
  EXPECT_EQ(sniff_image_format("Pf\n"), ImageFormat::pnm);
  EXPECT_EQ(sniff_image_format("\xff\xd8\xff\xe0"), ImageFormat::jpeg);
  EXPECT_EQ(sniff_image_format(std::string("II*\0", 4)), ImageFormat::tiff);
  EXPECT_EQ(sniff_image_format(std::string("MM\0+", 4)), ImageFormat::tiff);  // BigTIFF
  EXPECT_EQ(sniff_image_format("P7 not pnm"), std::nullopt);
  EXPECT_EQ(sniff_image_format(""), std::nullopt);
  EXPECT_EQ(sniff_image_format("BM"), std::nullopt);  // BMP is not read
  EXPECT_EQ(output_image_format("a.PNG"), ImageFormat::png);
  EXPECT_EQ(output_image_format("dir/a.exr"), ImageFormat::exr);
  EXPECT_THROW(output_image_format("a.jpg", "-o"), IoError);
  EXPECT_THROW(output_image_format("noext", "-o"), IoError);
}

// ---- the sRGB curve by table (issue 27): the same codes and floats as the pow-based curve ----

// What encode_image wrote into an 8-bit PNG before its table: the curve in double, rounded.
int curve_code(float x) { return int(std::lround(color::srgb_encode(double(x)) * 255.0)); }

// Every float in [0, 1] gives the curve's code. The floats are swept in steps of 97 bit patterns,
// every pattern within 4096 of each of the 255 steps of the code (found here by bisection on the
// curve), and the edges: zeros, NaNs, infinities, denormals, the curve's knee, values above 1.
// HYDROLUX_TEST_EXHAUSTIVE=1 checks every one of the 1,065,353,217 floats in [0, 1] (a minute).
TEST(SrgbTables, EncodeGivesTheCurvesCodeForEveryFloat) {
  constexpr std::uint32_t kOne = 0x3F800000u;
  const bool exhaustive = std::getenv("HYDROLUX_TEST_EXHAUSTIVE") != nullptr;
  std::uint64_t checked = 0, wrong = 0;
  const auto check = [&](std::uint32_t bits) {
    const float x = std::bit_cast<float>(bits);
    ++checked;
    if (srgb8_code(x) != curve_code(x) && ++wrong <= 5) ADD_FAILURE() << "bits " << bits << " x " << x;
  };
  for (std::uint64_t b = 0; b <= kOne; b += exhaustive ? 1 : 97) check(std::uint32_t(b));
  for (int k = 1; k <= 255; ++k) {
    std::uint32_t lo = 0, hi = kOne;  // curve_code(lo) < k <= curve_code(hi)
    while (hi - lo > 1) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      (curve_code(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
    }
    for (std::uint32_t b = hi - std::min<std::uint32_t>(hi, 4096); b <= std::min(hi + 4096, kOne); ++b) check(b);
  }
  EXPECT_EQ(wrong, 0u) << "of " << checked;
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (float x : {0.0f, -0.0f, 1.0f, nan, -nan, inf, -inf, -1.0f, 2.0f, 1e30f, std::numeric_limits<float>::denorm_min(),
                  std::numeric_limits<float>::min(), 0.0031308f, std::nextafter(0.0031308f, 0.0f),
                  std::nextafter(0.0031308f, 1.0f), std::nextafter(1.0f, 0.0f), std::nextafter(1.0f, 2.0f), 0.5f})
    EXPECT_EQ(int(srgb8_code(x)), curve_code(x)) << x;
  EXPECT_EQ(srgb8_code(nan), 0);
  EXPECT_EQ(srgb8_code(inf), 255);
  EXPECT_EQ(srgb8_code(0.5f), 188);  // 0.7353569 * 255 = 187.52
  std::vector<float> xs = {0.25f, nan, 0.75f};
  std::vector<std::uint8_t> codes(3);
  srgb8_codes(xs.data(), xs.size(), codes.data());
  EXPECT_EQ(codes, (std::vector<std::uint8_t>{srgb8_code(0.25f), 0, srgb8_code(0.75f)}));
}

// The decode the tables replace: OpenImageIO reads the file as floats and each colour value (not the
// alpha) goes through color::srgb_decode<float>, as decode_image did before its tables.
std::vector<float> curve_decode(const std::string& bytes, const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("hydrolux_test_curve_" + std::to_string(::getpid()) + "_" + name);
  { std::ofstream(p, std::ios::binary) << bytes; }
  auto in = OIIO::ImageInput::open(p.string());
  EXPECT_TRUE(in) << name;
  if (!in) return {};
  const OIIO::ImageSpec spec = in->spec();
  std::vector<float> px(std::size_t(spec.image_pixels()) * std::size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) << name;
  in->close();
  fs::remove(p);
  if (!spec.format.is_floating_point())
    for (std::size_t i = 0; i < px.size(); ++i)
      if (int(i % std::size_t(spec.nchannels)) != spec.alpha_channel) px[i] = color::srgb_decode(px[i]);
  return px;
}

std::string encode_codes(int w, int h, int c, OIIO::TypeDesc type, const void* codes) {
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput proxy(buffer);
  auto out = OIIO::ImageOutput::create("png");
  OIIO::ImageSpec spec(w, h, c, type);
  void* proxy_ptr = &proxy;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  EXPECT_TRUE(out->open("codes.png", spec) && out->write_image(type, codes) && out->close());
  return std::string(buffer.begin(), buffer.end());
}

bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Every 8-bit code (in RGB and in RGBA, whose alpha stays linear) and every 16-bit code decode to the
// very floats of the curve, and so does every 8- and 16-bit file of the fuzzers' seeds (PNG, palette
// PNG, PPM, PGM, JPEG, TIFF) and the float formats, which keep their old path.
TEST(SrgbTables, DecodeGivesTheCurvesFloatsForEveryCode) {
  for (int c : {1, 3, 4}) {
    std::vector<std::uint8_t> codes(std::size_t(256) * std::size_t(c));
    for (std::size_t i = 0; i < codes.size(); ++i) codes[i] = std::uint8_t((i / std::size_t(c) + i % std::size_t(c) * 85) % 256);
    const std::string png = encode_codes(256, 1, c, OIIO::TypeDesc::UINT8, codes.data());
    EXPECT_TRUE(same_floats(decode_image(png, "codes8.png").image.pixels, curve_decode(png, "codes8.png"))) << c;
  }
  std::vector<std::uint16_t> codes16(65536);
  for (std::size_t i = 0; i < codes16.size(); ++i) codes16[i] = std::uint16_t(i);
  const std::string png16 = encode_codes(256, 256, 1, OIIO::TypeDesc::UINT16, codes16.data());
  EXPECT_TRUE(same_floats(decode_image(png16, "codes16.png").image.pixels, curve_decode(png16, "codes16.png")));
  for (const char* name : {"drop.png", "palette.png", "drop.ppm", "ascii.ppm", "gray.pgm", "drop.jpg", "progressive.jpg",
                           "drop.tif", "tiled.tif", "drop.exr", "drop.hdr", "tiny.pfm"}) {
    std::string bytes = seed(name);
    if (sniff_image_format(bytes) == ImageFormat::jpeg) bytes = jpeg_without_metadata(bytes);  // as decoded
    EXPECT_TRUE(same_floats(decode_image(bytes, name).image.pixels, curve_decode(bytes, name))) << name;
  }
}

// The codes libpng (through OpenImageIO, alpha left unassociated) reads from a PNG, and the
// file's chunk types in order.
std::vector<std::uint16_t> libpng_codes(const std::string& png, std::vector<std::string>* chunks = nullptr) {
  OIIO::Filesystem::IOMemReader proxy(const_cast<char*>(png.data()), png.size());
  OIIO::ImageSpec config;
  void* proxy_ptr = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::create("png");
  OIIO::ImageSpec spec;
  EXPECT_TRUE(in->open("x.png", spec, config)) << in->geterror();
  std::vector<std::uint16_t> codes(spec.image_pixels() * std::size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT16, codes.data())) << in->geterror();
  EXPECT_EQ(in->geterror(), "");
  if (spec.format == OIIO::TypeDesc::UINT8)
    for (auto& c : codes) c = std::uint16_t(c / 257);  // OpenImageIO widens 8-bit codes by 257
  if (chunks)
    for (std::size_t pos = 8; pos + 8 <= png.size();) {
      const auto u8 = [&](std::size_t at) { return std::uint32_t(static_cast<unsigned char>(png[at])); };
      chunks->push_back(png.substr(pos + 4, 4));
      pos += 12 + (u8(pos) << 24 | u8(pos + 1) << 16 | u8(pos + 2) << 8 | u8(pos + 3));
    }
  return codes;
}

// The codes a PNG of `img` must hold: colour through the curve, unassociated from alpha in linear
// light for RGBA (hydrolux's RGBA images carry colour multiplied by alpha; PNG stores it divided),
// alpha linear.
std::vector<std::uint16_t> curve_codes(const Image& img, double max_code) {
  std::vector<std::uint16_t> codes(img.pixels.size());
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const float* px = img.pixels.data() + i / std::size_t(img.channels) * std::size_t(img.channels);
    double v = 0;
    if (img.channels == 4 && i % 4 == 3) v = std::clamp(double(img.pixels[i]), 0.0, 1.0);
    else if (img.channels == 4) v = color::srgb_encode(double(px[3] > 0 ? img.pixels[i] / px[3] : 0.0f));
    else v = color::srgb_encode(double(img.pixels[i]));
    codes[i] = std::uint16_t(std::lround(v * max_code));
  }
  return codes;
}

// encode_image's PNGs (libdeflate, io/png_codec.cpp) read back through libpng as the curve's codes,
// 8- and 16-bit, on images with NaN, infinite, negative, above-1 and random values, in grey, RGB and
// RGBA, at every level, with sRGB, gAMA and cHRM before the image data; higher levels are smaller;
// levels outside 0-9 are refused.
TEST(SrgbTables, EncodeWritesTheCurvesCodesAtEveryLevel) {
  std::vector<Image> images;
  for (int c : {1, 2, 3, 4}) {
    Image img(97, 31, c);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    for (float& v : img.pixels) v = u(rng);
    img.pixels[0] = std::numeric_limits<float>::quiet_NaN();
    img.pixels[1] = -std::numeric_limits<float>::infinity();
    img.pixels[5] = std::numeric_limits<float>::infinity();
    if (c == 4) img.pixels[7] = 0.0f;  // a transparent pixel: black
    images.push_back(std::move(img));
  }
  images.push_back(gradient(256, 64, 3));
  for (const Image& img : images) {
    for (int level = 0; level <= kMaxPngCompression; ++level) {
      std::vector<std::string> chunks;
      EXPECT_EQ(libpng_codes(encode_image(img, ImageFormat::png, {8, level}), &chunks), curve_codes(img, 255.0))
          << "level " << level << ", " << img.channels << " channels";
      EXPECT_EQ(chunks, (std::vector<std::string>{"IHDR", "sRGB", "gAMA", "cHRM", "IDAT", "IEND"}));
    }
    for (int level : {0, 1, 6})
      EXPECT_EQ(libpng_codes(encode_image(img, ImageFormat::png, {16, level})), curve_codes(img, 65535.0))
          << "16 bits, level " << level << ", " << img.channels << " channels";
  }
  const Image& smooth = images.back();
  EXPECT_LT(encode_image(smooth, ImageFormat::png, {8, 9}).size(), encode_image(smooth, ImageFormat::png, {8, 1}).size());
  EXPECT_LT(encode_image(smooth, ImageFormat::png, {8, 1}).size(), encode_image(smooth, ImageFormat::png, {8, 0}).size());
  for (int bad : {-1, 10, 100})
    EXPECT_NE(message_of([&] { (void)encode_image(smooth, ImageFormat::png, {8, bad}); }).find("compression level"),
              std::string::npos)
        << bad;
  EXPECT_NO_THROW((void)encode_image(smooth, ImageFormat::exr, {8, 10}));  // EXR has its own compression
}

// Same image, same bytes: EXR carries no time stamp (OpenImageIO would write DateTime/capDate with
// the time of writing), PNG none either. Encoded more than a second apart, as the stamp has
// one-second resolution.
TEST(ImageFormats, EncodingIsDeterministic) {
  Image img(16, 8, 4);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(i) / 512.f;
  const std::string exr1 = encode_image(img, ImageFormat::exr), png1 = encode_image(img, ImageFormat::png);
  const std::string png16 = encode_image(img, ImageFormat::png, {16});
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  EXPECT_EQ(encode_image(img, ImageFormat::exr), exr1);
  EXPECT_EQ(encode_image(img, ImageFormat::png), png1);
  EXPECT_EQ(encode_image(img, ImageFormat::png, {16}), png16);
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char year[8];
  std::strftime(year, sizeof year, "%Y:", std::gmtime(&now));
  EXPECT_EQ(exr1.find(year), std::string::npos) << "the EXR carries a date";
}

}  // namespace
}  // namespace hydrolux::io
