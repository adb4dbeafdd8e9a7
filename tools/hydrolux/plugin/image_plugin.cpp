// The CLI's image plugin (see ../image_plugin.hpp): OpenImageIO's codecs and the gallery behind one
// symbol.
#include "../image_plugin.hpp"

#include "hydrolux/gallery/gallery.hpp"
#include "hydrolux/io/image_io.hpp"

namespace {

hydrolux::io::DecodedImage decode(std::string_view bytes, std::string_view origin,
                                  const hydrolux::io::ImageLimits& limits) {
  return hydrolux::io::decode_image(bytes, origin, limits);
}

std::string encode(const hydrolux::Image& image, hydrolux::io::ImageFormat format, hydrolux::io::PngOptions png) {
  return hydrolux::io::encode_image(image, format, png);
}

std::vector<hydrolux::gallery::Figure> gallery(const hydrolux::gallery::FigureSink& sink,
                                               const hydrolux::ProgressFn& progress) {
  return hydrolux::gallery::render_gallery(sink, progress);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const hydrolux::cli::ImageApi* hydrolux_image_api_v2() {
  static const hydrolux::cli::ImageApi api{&decode, &encode, &gallery};
  return &api;
}
