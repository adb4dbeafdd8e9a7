#include "video_plugin.hpp"

#include "plugin_loader.hpp"

namespace hydrolux::cli {

const VideoApi& video_api() {
  // A failed load throws and is retried on the next call.
  static const VideoApi& api =
      *reinterpret_cast<const VideoApi* (*)()>(plugin_entry(kVideoPluginFile, kVideoPluginSymbol, "video"))();
  return api;
}

}  // namespace hydrolux::cli
