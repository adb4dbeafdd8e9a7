#include "hydrolux/core/embedded_data.hpp"

#include <fmt/format.h>

#include "hydrolux/core/error.hpp"

namespace hydrolux {

std::string_view embedded_file(std::string_view path) {
  for (const auto& f : detail::embedded_files())
    if (f.path == path) return f.text;
  throw IoError(fmt::format("no data file 'data/{}' is built into hydrolux", path));
}

}  // namespace hydrolux
