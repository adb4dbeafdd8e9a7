#pragma once
// The frame driver's hooks (io/frame_driver.hpp) as every frame command sets them: the image plugin,
// warnings on stderr (the progress bar erased first) and the progress bar.
#include <string>
#include <string_view>

#include "common.hpp"
#include "hydrolux/io/frame_driver.hpp"
#include "image_plugin.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

inline io::FrameHooks frame_hooks(ProgressBar& bar) {
  io::FrameHooks hooks;
  hooks.codec = image_codec();  // the plugin loads on first use: a video run never loads OpenImageIO
  hooks.warn = [&bar](const std::string& text) {
    bar.clear();
    warn(text);
  };
  hooks.progress = [&bar](double f, std::string_view label) { bar.update(f, label); };
  hooks.clear_progress = [&bar] { bar.clear(); };
  hooks.finish_progress = [&bar] { bar.finish(); };
  return hooks;
}

}  // namespace hydrolux::cli
