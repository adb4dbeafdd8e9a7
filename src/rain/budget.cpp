// The memory a rendering needs against what is available (rain.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::rain {

void check_render_memory(const RainCamera& c, int input_channels, bool with_layer, const std::string& what,
                         double extra_bytes_per_pixel) {
  const double need = double(estimated_render_bytes(c, input_channels, with_layer, extra_bytes_per_pixel));
  const double avail = double(available_memory_bytes());
  if (need <= avail) return;
  // What grows with the pixels scales; the program and the drops do not.
  RainCamera none = c;
  none.width = none.height = 0;
  const double fixed = double(estimated_render_bytes(none, input_channels, with_layer, extra_bytes_per_pixel));
  const double scale = std::sqrt(std::max(0.0, avail - fixed) / (need - fixed));
  throw Error(fmt::format("{}: rain over {}x{} needs about {} of memory and {} is available; about {}x{} would fit",
                          what, c.width, c.height, format_bytes(need), format_bytes(avail),
                          int(std::floor(c.width * scale)), int(std::floor(c.height * scale))));
}

}  // namespace hydrolux::rain
