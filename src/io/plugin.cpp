#include "hydrolux/io/plugin.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "hydrolux/core/error.hpp"

namespace hydrolux::io {

void* plugin_entry(const char* file_name, const char* symbol, const char* what) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const auto file = (ec ? std::filesystem::path(".") : exe.parent_path()) / file_name;
  void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    throw Error(fmt::format("{} support is unavailable: cannot load {} ({})", what, file.string(), why ? why : "?"));
  }
  void* entry = ::dlsym(handle, symbol);
  if (!entry) throw Error(fmt::format("{} support is unavailable: {} has no {}", what, file.string(), symbol));
  return entry;
}

}  // namespace hydrolux::io
