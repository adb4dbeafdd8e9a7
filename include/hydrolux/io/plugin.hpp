#pragma once
// Loading a plugin built beside the executable (the CLI's libhydrolux_image_plugin.so and
// libhydrolux_video_plugin.so, io/video.hpp): the module is opened from the running executable's
// folder and its one `extern "C"` entry point returned.
namespace hydrolux::io {

// dlopen(<executable's folder>/<file>) and dlsym(symbol). Throws hydrolux::Error "<what> support is
// unavailable: ..." naming the file and the loader's reason. The module stays loaded for the life
// of the process.
void* plugin_entry(const char* file, const char* symbol, const char* what);

}  // namespace hydrolux::io
