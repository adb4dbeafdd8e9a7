#pragma once
// The sRGB transfer function (IEC 61966-2-1:1999): linear scene values <-> display-encoded values.
#include <cmath>

namespace hydrolux::color {

// Linear [0, 1] -> encoded [0, 1]; values outside [0, 1] are clamped.
template <typename Float>
Float srgb_encode(Float linear) noexcept {
  if (!(linear > Float(0))) return Float(0);
  if (linear >= Float(1)) return Float(1);
  return linear <= Float(0.0031308) ? Float(12.92) * linear
                                     : Float(1.055) * std::pow(linear, Float(1) / Float(2.4)) - Float(0.055);
}

// Encoded [0, 1] -> linear [0, 1].
template <typename Float>
Float srgb_decode(Float encoded) noexcept {
  if (!(encoded > Float(0))) return Float(0);
  if (encoded >= Float(1)) return Float(1);
  return encoded <= Float(0.04045) ? encoded / Float(12.92)
                                   : std::pow((encoded + Float(0.055)) / Float(1.055), Float(2.4));
}

}  // namespace hydrolux::color
