// Loading the video plugin: see hydrolux/io/video.hpp. The FFmpeg implementation is
// video_ffmpeg.cpp, built apart (the object library hydrolux_video) so that hydrolux_io does not
// link FFmpeg.
#include "hydrolux/io/video.hpp"

#include "hydrolux/io/plugin.hpp"

namespace hydrolux::io {

const VideoApi& video_api() {
  // A failed load throws and is retried on the next call.
  static const VideoApi& api =
      *reinterpret_cast<const VideoApi* (*)()>(plugin_entry(kVideoPluginFile, kVideoPluginSymbol, "video"))();
  return api;
}

}  // namespace hydrolux::io
