#include "image_plugin.hpp"

#include "hydrolux/io/plugin.hpp"

namespace hydrolux::cli {

const ImageApi& image_api() {
  // A failed load throws and is retried on the next call.
  static const ImageApi& api =
      *reinterpret_cast<const ImageApi* (*)()>(io::plugin_entry(kImagePluginFile, kImagePluginSymbol, "image"))();
  return api;
}

}  // namespace hydrolux::cli
