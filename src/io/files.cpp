#include "hydrolux/io/files.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "hydrolux/core/error.hpp"

namespace hydrolux::io {

namespace fs = std::filesystem;

fs::path temporary_path_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const auto dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  return dir / fmt::format(".{}.tmp-{}-{}{}", target.stem().string(), ::getpid(), counter++,
                           target.extension().string());
}

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  std::error_code ec;
  if (target.has_parent_path()) {
    fs::create_directories(target.parent_path(), ec);
    if (ec)
      throw IoError(fmt::format("cannot create directory '{}': {}", target.parent_path().string(),
                                ec.message()));
  }
  if (fs::is_directory(target, ec))
    throw IoError(fmt::format("cannot write '{}': it is a directory", target.string()));
  const fs::path tmp = temporary_path_for(target);
  try {
    write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw IoError(fmt::format("cannot write '{}': {}", target.string(), ec.message()));
  }
}

void write_text_file(const fs::path& target, std::string_view text) {
  write_atomically(target, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw IoError(fmt::format("cannot write '{}': {}", target.string(), std::strerror(errno)));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw IoError(fmt::format("cannot write '{}': write failed", target.string()));
  });
}

}  // namespace hydrolux::io
