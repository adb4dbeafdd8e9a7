// The memory a rendering needs against what is available (rain.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "hydrolux/rain/rain.hpp"

namespace hydrolux::rain {

void check_frame_memory(const std::string& what, const std::string& job, int width, int height, std::uint64_t need,
                        std::uint64_t fixed) {
  const double avail = double(available_memory_bytes());
  if (double(need) <= avail) return;
  // What grows with the pixels scales; the program and the drops do not.
  const double scale = std::sqrt(std::max(0.0, avail - double(fixed)) / std::max(1.0, double(need) - double(fixed)));
  throw Error(fmt::format("{}: {} over {}x{} needs about {} of memory and {} is available; about {}x{} would fit", what,
                          job, width, height, format_bytes(double(need)), format_bytes(avail),
                          int(std::floor(width * scale)), int(std::floor(height * scale))));
}

void check_render_memory(const RainCamera& c, int input_channels, bool with_layer, const std::string& what,
                         double extra_bytes_per_pixel) {
  RainCamera none = c;
  none.width = none.height = 0;
  check_frame_memory(what, "rain", c.width, c.height,
                     estimated_render_bytes(c, input_channels, with_layer, extra_bytes_per_pixel),
                     estimated_render_bytes(none, input_channels, with_layer, extra_bytes_per_pixel));
}

// Fog: the decoded frame and the foggy one (4 bytes a channel each), the transmittance (8), optical
// depth, range and depth (4 each), the in-scattered source (12), the veil and the alpha, and the
// encoder's scratch; the glow's blurred source at several scales. Measured peak resident size of
// `hydrolux fog --visibility-m 200` over an incompressible 8-bit PNG (2026-11-28): 423 MB at 2048^2
// and 1.29 GB at 4096^2 with the glow (69 bytes a pixel above 135 MB), 870 MB at 4096^2 without it;
// the bound below is 16-24% above each.
std::uint64_t estimated_fog_bytes(int width, int height, int channels, bool glow, double extra_bytes_per_pixel) {
  constexpr double kFixedBytes = 160e6;
  const double per_pixel = 8.0 * std::max(3, channels) + (glow ? 56 : 31) + extra_bytes_per_pixel;
  return std::uint64_t(kFixedBytes + per_pixel * double(width) * double(height));
}

// Lens drops: the decoded frame and the output (4 bytes a channel each), the sharp layer and its
// blur (4 bytes a light channel each), the coverage and the mask, the blur's prefix sums (8 bytes
// over the row padded by the disk's radius) and the encoder's scratch. Measured peak resident size of
// `hydrolux lens-drops` (defaults, a 117 px blur at 4096) over an incompressible 8-bit PNG
// (2026-11-28): 368 MB at 2048^2, 1.08 GB at 4096^2 (56 bytes a pixel above 132 MB); the bound below
// is 14-16% above each (the prefix sums' share grows with the blur, at most 16 bytes a pixel).
std::uint64_t estimated_lens_drops_bytes(int width, int height, int channels, double blur_diameter_px) {
  constexpr double kFixedBytes = 160e6;
  const double light = channels >= 3 ? 3 : 1;
  const double w = std::max(1, width);
  const double prefix = 8 * (w + blur_diameter_px + 6) / w;
  const double per_pixel = 8.0 * std::max(1, channels) + 4 * light + 20 + prefix;
  return std::uint64_t(kFixedBytes + per_pixel * double(width) * double(height));
}

void check_fog_memory(const std::string& what, int width, int height, int channels, bool glow) {
  check_frame_memory(what, "fog", width, height, estimated_fog_bytes(width, height, channels, glow),
                     estimated_fog_bytes(0, 0, channels, glow));
}

void check_lens_drops_memory(const LensDropSettings& s, const std::string& what, int width, int height,
                             int channels, double extra_bytes_per_pixel) {
  const double blur =
      circle_of_confusion_mm(s.focal_mm, s.f_number, s.focus_m, s.glass_distance_m) / s.sensor_width_mm * width;
  const auto extra = std::uint64_t(extra_bytes_per_pixel * double(width) * double(height));
  check_frame_memory(what, "lens drops", width, height, estimated_lens_drops_bytes(width, height, channels, blur) + extra,
                     estimated_lens_drops_bytes(0, 0, channels, 0));
}

}  // namespace hydrolux::rain
