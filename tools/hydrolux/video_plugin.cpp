#include "video_plugin.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "hydrolux/core/error.hpp"

namespace hydrolux::cli {

namespace {
const VideoApi& load() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const auto file = (ec ? std::filesystem::path(".") : exe.parent_path()) / kVideoPluginFile;
  void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    throw Error(fmt::format("video support is unavailable: cannot load {} ({})", file.string(), why ? why : "?"));
  }
  using Entry = const VideoApi* (*)();
  const auto entry = reinterpret_cast<Entry>(::dlsym(handle, kVideoPluginSymbol));
  if (!entry) throw Error(fmt::format("video support is unavailable: {} has no {}", file.string(), kVideoPluginSymbol));
  return *entry();  // the library stays loaded for the life of the process
}
}  // namespace

const VideoApi& video_api() {
  static const VideoApi& api = load();  // a failed load throws and is retried on the next call
  return api;
}

}  // namespace hydrolux::cli
