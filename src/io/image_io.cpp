#include "hydrolux/io/image_io.hpp"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "hydrolux/color/srgb.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

template <typename T>
std::vector<T> quantise_srgb(const Image& img, double max_code) {
  std::vector<T> out(img.pixels.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    // Alpha (4th channel) is stored linearly, colour through the sRGB curve.
    const bool alpha = img.channels == 4 && i % 4 == 3;
    const double v = alpha ? std::clamp(double(img.pixels[i]), 0.0, 1.0)
                           : color::srgb_encode(double(img.pixels[i]));
    out[i] = static_cast<T>(std::lround(v * max_code));
  }
  return out;
}

}  // namespace

Image read_image(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw IoError(fmt::format("cannot read image '{}': no such file", path.string()));
  auto in = OIIO::ImageInput::open(path.string());
  if (!in)
    throw IoError(fmt::format("cannot read image '{}': {}", path.string(), OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw IoError(fmt::format("cannot read image '{}': empty image", path.string()));
  Image img(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
    throw IoError(fmt::format("cannot read image '{}': {}", path.string(), in->geterror()));
  const bool is_float = spec.format.is_floating_point();
  in->close();
  if (!is_float) {
    for (std::size_t i = 0; i < img.pixels.size(); ++i) {
      const bool alpha = img.channels == 4 && i % 4 == 3;
      if (!alpha) img.pixels[i] = color::srgb_decode(img.pixels[i]);
    }
  }
  return img;
}

void write_image(const fs::path& path, const Image& image, PngOptions png) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0 ||
      image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
    throw IoError(fmt::format("cannot write image '{}': inconsistent image dimensions", path.string()));
  const std::string ext = lower_extension(path);
  if (ext != ".exr" && ext != ".png")
    throw IoError(fmt::format("cannot write image '{}': unsupported extension '{}' (use .exr or .png)",
                              path.string(), ext));
  if (ext == ".png" && png.bits != 8 && png.bits != 16)
    throw IoError(fmt::format("cannot write image '{}': PNG bit depth {} (use 8 or 16)", path.string(),
                              png.bits));

  write_atomically(path, [&](const fs::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out)
      throw IoError(fmt::format("cannot write image '{}': {}", path.string(), OIIO::geterror()));
    OIIO::TypeDesc format = OIIO::TypeDesc::FLOAT;
    std::vector<std::uint8_t> px8;
    std::vector<std::uint16_t> px16;
    const void* data = image.pixels.data();
    if (ext == ".png") {
      if (png.bits == 8) {
        px8 = quantise_srgb<std::uint8_t>(image, 255.0);
        format = OIIO::TypeDesc::UINT8;
        data = px8.data();
      } else {
        px16 = quantise_srgb<std::uint16_t>(image, 65535.0);
        format = OIIO::TypeDesc::UINT16;
        data = px16.data();
      }
    }
    OIIO::ImageSpec spec(image.width, image.height, image.channels, format);
    spec.attribute("oiio:ColorSpace", ext == ".png" ? "sRGB" : "linear");
    if (ext == ".exr") spec.attribute("compression", "zip");
    if (!out->open(tmp.string(), spec) || !out->write_image(format, data) || !out->close())
      throw IoError(fmt::format("cannot write image '{}': {}", path.string(), out->geterror()));
  });
}

}  // namespace hydrolux::io
