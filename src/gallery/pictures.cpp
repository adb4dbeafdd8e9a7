// The gallery's helpers for figures made as pictures (entries.hpp): panels laid out side by side or
// stacked, crops, masks as --mask-out writes them, and the built-in street's camera.
#include <algorithm>
#include <vector>

#include "entries.hpp"
#include "hydrolux/color/srgb.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr float kBackground = 0.02f;  // the dark grey between panels

}  // namespace

Image side_by_side(const std::vector<Image>& panels, int gap) {
  int w = 0;
  for (const auto& p : panels) w += p.width + gap;
  Image out(w - gap, panels.front().height, 3);
  std::fill(out.pixels.begin(), out.pixels.end(), kBackground);
  int x0 = 0;
  for (const auto& p : panels) {
    for (int y = 0; y < p.height; ++y)
      for (int x = 0; x < p.width; ++x)
        for (int c = 0; c < 3; ++c) out.at(x0 + x, y, c) = p.at(x, y, c);
    x0 += p.width + gap;
  }
  return out;
}

Image stacked(const std::vector<Image>& rows, int gap) {
  int w = 0, h = -gap;
  for (const auto& r : rows) w = std::max(w, r.width), h += r.height + gap;
  Image out(w, h, 3);
  std::fill(out.pixels.begin(), out.pixels.end(), kBackground);
  int y0 = 0;
  for (const auto& r : rows) {
    const int x0 = (w - r.width) / 2;
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x)
        for (int k = 0; k < 3; ++k) out.at(x0 + x, y0 + y, k) = r.at(x, y, k);
    y0 += r.height + gap;
  }
  return out;
}

Image crop(const Image& img, int x0, int y0, int w, int h) {
  Image out(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = img.at(x0 + x, y0 + y, std::min(k, img.channels - 1));
  return out;
}

Image mask_picture(const Image& mask) {
  Image out(mask.width, mask.height, 3);
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x)
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = float(color::srgb_decode(double(mask.at(x, y, 0))));
  return out;
}

rain::RainCamera street_camera(int width, int height) {
  rain::RainCamera c;
  c.width = width;
  c.height = height;
  c.focal_mm = 35;
  return c;
}

}  // namespace hydrolux::gallery::detail
