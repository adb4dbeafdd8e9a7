// 8-bit sRGB tables (color/srgb.hpp).
#include "hydrolux/color/srgb.hpp"

#include <algorithm>

namespace hydrolux::color {

Srgb8Tables::Srgb8Tables() : encode_(65536) {
  for (int i = 0; i < 256; ++i) decode_[std::size_t(i)] = float(srgb_decode(i / 255.0));
  for (int i = 0; i < 65536; ++i)
    encode_[std::size_t(i)] = std::uint8_t(std::lround(std::clamp(srgb_encode(i / 65535.0), 0.0, 1.0) * 255));
}

void Srgb8Tables::to_linear(const std::uint8_t* rgb8, std::size_t pixels, float* linear) const {
  for (std::size_t i = 0; i < pixels * 3; ++i) linear[i] = decode_[rgb8[i]];
}

void Srgb8Tables::to_srgb8(const float* linear, std::size_t pixels, int channels, std::uint8_t* rgb8) const {
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t k = 0; k < 3; ++k) {
      const float v = std::clamp(linear[p * std::size_t(channels) + k], 0.f, 1.f);
      rgb8[p * 3 + k] = encode_[std::size_t(v * 65535.f + 0.5f)];
    }
}

}  // namespace hydrolux::color
