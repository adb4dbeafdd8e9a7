// The CLI's image plugin (see ../image_plugin.hpp): OpenImageIO and the gallery behind one symbol.
#include "../image_plugin.hpp"

#include "hydrolux/gallery/gallery.hpp"
#include "hydrolux/io/image_io.hpp"

namespace {

hydrolux::Image read(const std::filesystem::path& path) { return hydrolux::io::read_image(path); }

void write(const std::filesystem::path& path, const hydrolux::Image& image, hydrolux::io::PngOptions png) {
  hydrolux::io::write_image(path, image, png);
}

std::vector<hydrolux::gallery::Figure> gallery(const std::filesystem::path& dir, const hydrolux::ProgressFn& progress) {
  return hydrolux::gallery::write_gallery(dir, progress);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const hydrolux::cli::ImageApi* hydrolux_image_api_v1() {
  static const hydrolux::cli::ImageApi api{&read, &write, &gallery};
  return &api;
}
