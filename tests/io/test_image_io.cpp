// Image files: EXR round trip, PNG through the sRGB curve, errors, atomic writes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"

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

// A failed write leaves an existing file untouched and no temporary file behind.
TEST_F(ImageIo, FailedWriteNeverClobbers) {
  const Image img = gradient(4, 4, 3);
  write_image(dir_ / "keep.exr", img);
  const auto size_before = fs::file_size(dir_ / "keep.exr");
  EXPECT_THROW(write_atomically(dir_ / "keep.exr",
                                [](const fs::path& tmp) {
                                  std::ofstream(tmp) << "partial";
                                  throw IoError("simulated failure mid-write");
                                }),
               IoError);
  EXPECT_EQ(fs::file_size(dir_ / "keep.exr"), size_before);
  EXPECT_EQ(read_image(dir_ / "keep.exr").pixels, img.pixels);
  EXPECT_EQ(file_count(), 1u);
  // A directory in the way is an error, not a crash.
  fs::create_directories(dir_ / "adir");
  EXPECT_THROW(write_text_file(dir_ / "adir", "x"), IoError);
}

TEST_F(ImageIo, TextFilesAndDirectories) {
  write_text_file(dir_ / "sub" / "deeper" / "t.txt", "hello\n");
  std::ifstream in(dir_ / "sub" / "deeper" / "t.txt");
  std::string s;
  std::getline(in, s);
  EXPECT_EQ(s, "hello");
  EXPECT_EQ(temporary_path_for(dir_ / "a.png").extension(), ".png");
  EXPECT_EQ(temporary_path_for(dir_ / "a.png").parent_path(), dir_);
}

}  // namespace
}  // namespace hydrolux::io
