#pragma once
// The sRGB transfer function (IEC 61966-2-1:1999): linear scene values <-> display-encoded values.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

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

// 8-bit sRGB codes <-> linear floats by table, for video frames: decode indexes the 256 codes;
// encode indexes the linear value, clamped to [0, 1], in steps of 1/65535 (finer than any 8-bit
// code's width), rounding to the nearest code. `hydrolux rain --video` and the Python batch use the
// same tables, so they write the same bytes.
class Srgb8Tables {
 public:
  Srgb8Tables();
  float decode(std::uint8_t code) const { return decode_[code]; }
  // `pixels` RGB pixels from rgb8 (3 bytes each) to linear floats (3 each).
  void to_linear(const std::uint8_t* rgb8, std::size_t pixels, float* linear) const;
  // The first three of `channels` floats per pixel to 3 bytes per pixel.
  void to_srgb8(const float* linear, std::size_t pixels, int channels, std::uint8_t* rgb8) const;

 private:
  std::array<float, 256> decode_{};
  std::vector<std::uint8_t> encode_;
};

}  // namespace hydrolux::color
