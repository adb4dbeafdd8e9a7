#pragma once
// Image coding and the gallery for the CLI, through a plugin loaded on first use.
//
// OpenImageIO brings ~260 shared libraries that take ~0.35 s to load. Linked into the tool, every
// command would pay that at start-up, `hydrolux fresnel` included; loaded with dlopen from
// libhydrolux_image_plugin.so (built beside the executable) only the commands that read or write
// images, or render the gallery, pay it, once. The plugin is built from the same sources and
// compiler as the tool, so C++ types and exceptions cross the boundary unchanged.
//
// The plugin only encodes and decodes bytes in memory and renders figures: every file is read and
// written by the tool itself through io/files.hpp, so the tool's one registry of pending outputs
// sees them all and its Ctrl-C handler removes them (the plugin holds its own copy of the static
// libraries, whose registry would be invisible to the tool).
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/gallery/gallery.hpp"
#include "hydrolux/io/image_io.hpp"

namespace hydrolux::cli {

struct ImageApi {
  io::DecodedImage (*decode_image)(std::string_view bytes, std::string_view origin, const io::ImageLimits& limits);
  std::string (*encode_image)(const Image& image, io::ImageFormat format, io::PngOptions png);
  std::vector<gallery::Figure> (*render_gallery)(const gallery::FigureSink& sink, const ProgressFn& progress);
};

// The plugin's entry point, `extern "C"` so that its name is not mangled.
inline constexpr const char* kImagePluginSymbol = "hydrolux_image_api_v2";
inline constexpr const char* kImagePluginFile = "libhydrolux_image_plugin.so";

// Loads the plugin (once; thread-safe) from the directory of the running executable
// (hydrolux/io/plugin.hpp). Throws hydrolux::Error naming the file and the loader's reason if it cannot.
const ImageApi& image_api();
// The plugin's coder as the library takes it (io::ImageCodec), loading the plugin on first use only.
io::ImageCodec image_codec();

}  // namespace hydrolux::cli
