#include "image_plugin.hpp"

#include "hydrolux/io/plugin.hpp"

namespace hydrolux::cli {

const ImageApi& image_api() {
  // A failed load throws and is retried on the next call.
  static const ImageApi& api =
      *reinterpret_cast<const ImageApi* (*)()>(io::plugin_entry(kImagePluginFile, kImagePluginSymbol, "image"))();
  return api;
}

io::ImageCodec image_codec() {
  io::ImageCodec c;
  c.decode = [](std::string_view bytes, std::string_view origin, const io::ImageLimits& limits) {
    return image_api().decode_image(bytes, origin, limits);
  };
  c.encode = [](const Image& image, io::ImageFormat format, io::PngOptions png) {
    return image_api().encode_image(image, format, png);
  };
  return c;
}

}  // namespace hydrolux::cli
